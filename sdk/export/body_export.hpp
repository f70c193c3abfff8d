// A body written to a file as people and tools want it: the posed mesh (OBJ with UVs and normals,
// binary PLY) or the rigged body (binary glTF: bind pose, skeleton posed by the body's joints,
// skin). The C API's ssc_body_write_file and the command line's outputs come through here.
#pragma once

#include "export/morph_targets.hpp"
#include "synthesis/body.hpp"

#include <string>

namespace ssc::exporters {

enum class BodyFormat { Obj, Ply, Glb };

// The format a path names by its extension (.obj, .ply, .glb; any case); throws
// SSC_ERROR_INVALID_ARGUMENT naming the formats for anything else.
BodyFormat format_of(const std::string& path);

// level for every level of detail in one glTF file (one node each, NAME_LOD0, NAME_LOD1, ...).
inline constexpr uint32_t kAllLevels = 0xFFFFFFFFu;

struct ExportOptions {
    // 0 the full mesh, l > 0 the model's level of detail l - 1 (Model::level), with its own
    // triangles, UVs and skin; kAllLevels: all of them (glTF only).
    uint32_t level = 0;
    // glTF only: shape morph targets on every mesh, around the body's shape (morph_targets()).
    std::vector<MorphTarget> morphs;
};

// Writes the body (its current shape and pose) to path; the file appears whole or not at all.
// Throws ssc::Error: SSC_ERROR_IO when the file cannot be written, SSC_ERROR_INVALID_ARGUMENT for
// a level the model does not have, or several levels or morph targets in OBJ or PLY.
void write_body(Body& body, const std::string& path, BodyFormat format, const ExportOptions& options = {});

}  // namespace ssc::exporters
