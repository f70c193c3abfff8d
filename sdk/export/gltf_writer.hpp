// glTF 2.0 binary (.glb) export of a rigged body: the shaped mesh in its bind pose with normals and
// UVs (vertices split where UVs have seams), the skeleton as a node hierarchy posed by the body's
// local joint transforms, and a skin (joints, inverse bind matrices, 4 influences per vertex);
// levels of detail as more meshes on the same skeleton, one node each, named NAME_LOD0, _LOD1, ...
// (the suffix engines' importers look for). Engines and Blender import it as a rigged, posed character.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::exporters {

// One mesh bound to the skeleton: the full body or a level of detail.
struct RiggedMesh {
    std::string name = "body";
    uint32_t vertex_count = 0;
    const float* rest_positions = nullptr;   // 3 per vertex: the shaped body in the bind pose
    const float* rest_normals = nullptr;     // 3 per vertex, optional
    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;     // 3 per triangle
    uint32_t uv_count = 0;
    const float* uvs = nullptr;              // 2 per coordinate (OBJ convention, v up), optional
    const uint32_t* triangle_uvs = nullptr;  // 3 per triangle, with uvs
    const uint16_t* skin_joints = nullptr;   // 4 per vertex
    const float* skin_weights = nullptr;     // 4 per vertex
    // Per morph target of RiggedBody::morphs: the rest positions' and normals' change at weight 1,
    // 3 per vertex each (normals optional).
    std::vector<const float*> morph_positions, morph_normals;
};

// A shape morph target: its name and, for an engine that moves the joints with the shape, each
// joint's rest position change at weight 1 (3 per joint, world frame). info goes into the file's
// extras as it is (what one unit of weight means).
struct RiggedMorph {
    std::string name;
    std::vector<float> joint_offsets;
    std::string kind, unit;
    double per_weight = 1;
};

struct RiggedBody {
    // One node each, every one skinned by the one skeleton (levels of detail: finest first), all
    // with one skin material (PBR, a neutral albedo).
    std::vector<RiggedMesh> meshes;
    uint32_t joint_count = 0;
    const int32_t* parents = nullptr;        // -1 for the root; parents precede children
    std::vector<std::string> joint_names;
    const float* joint_world = nullptr;      // 16 per joint, column-major: posed world transforms
    const float* inverse_bind = nullptr;     // 16 per joint, column-major
    std::vector<RiggedMorph> morphs;         // every mesh has these morph targets, in this order
};

// Writes a .glb file (temporary file + rename). Every vertex carries _MODEL_VERTEX, its index in
// the mesh given (a float, exact below 2^24), as vertices split at UV seams no longer say it.
// With morphs, each mesh has its targets (names in the mesh's extras.targetNames, as Blender and
// three.js read them) and skins[0].extras.sscape_morphs says per target how the joint nodes'
// translations and the inverse bind matrices' translations change per unit of weight (docs/engines.md).
// Throws ssc::Error on bad input or I/O failure.
void write_glb(const std::string& path, const RiggedBody& body);

}  // namespace ssc::exporters
