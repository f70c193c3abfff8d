// Mesh files for people and tools: OBJ (text, with UVs and normals) and binary PLY.
// Files are written to a temporary name and renamed, so a failure leaves no partial file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::exporters {

struct MeshView {
    uint32_t vertex_count = 0;
    const float* positions = nullptr;      // 3 per vertex
    const float* normals = nullptr;        // 3 per vertex, optional
    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;   // 3 per triangle
    uint32_t uv_count = 0;
    const float* uvs = nullptr;            // 2 per coordinate, optional
    const uint32_t* triangle_uvs = nullptr;  // 3 per triangle, with uvs
};

void write_obj(const std::string& path, const MeshView& mesh);
void write_ply(const std::string& path, const MeshView& mesh);

// By extension (.obj or .ply, case-insensitive); SSC_ERROR_INVALID_ARGUMENT for anything else.
void write_mesh(const std::string& path, const MeshView& mesh);

// The bytes those write: OBJ text, binary PLY, or either by path's extension (as write_mesh).
std::string obj_bytes(const MeshView& mesh);
std::string ply_bytes(const MeshView& mesh);
std::string mesh_bytes(const std::string& path, const MeshView& mesh);

}  // namespace ssc::exporters
