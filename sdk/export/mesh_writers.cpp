#include "mesh_writers.hpp"

#include "common/files.hpp"
#include "common/error.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ssc::exporters {
namespace {

void commit(const std::string& path, const std::string& bytes) { write_file_atomically(path, bytes.data(), bytes.size()); }

}  // namespace

std::string obj_bytes(const MeshView& m) {
    std::string s;
    s.reserve(std::size_t(m.vertex_count) * 80 + std::size_t(m.triangle_count) * 40);
    char line[160];
    s += "# sscape body: metres, Y up, facing +Z\n";
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
        s += line;
    }
    const bool uv = m.uvs && m.triangle_uvs;
    if (uv)
        for (uint32_t t = 0; t < m.uv_count; ++t) {
            std::snprintf(line, sizeof line, "vt %.6f %.6f\n", m.uvs[2 * t], m.uvs[2 * t + 1]);
            s += line;
        }
    if (m.normals)
        for (uint32_t v = 0; v < m.vertex_count; ++v) {
            std::snprintf(line, sizeof line, "vn %.5f %.5f %.5f\n", m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
            s += line;
        }
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        s += 'f';
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = m.triangles[3 * t + c] + 1;
            if (uv && m.normals) std::snprintf(line, sizeof line, " %u/%u/%u", v, m.triangle_uvs[3 * t + c] + 1, v);
            else if (uv) std::snprintf(line, sizeof line, " %u/%u", v, m.triangle_uvs[3 * t + c] + 1);
            else if (m.normals) std::snprintf(line, sizeof line, " %u//%u", v, v);
            else std::snprintf(line, sizeof line, " %u", v);
            s += line;
        }
        s += '\n';
    }
    return s;
}

void write_obj(const std::string& path, const MeshView& m) { commit(path, obj_bytes(m)); }

std::string ply_bytes(const MeshView& m) {
    std::ostringstream h;
    h << "ply\nformat binary_little_endian 1.0\ncomment sscape body: metres, Y up, facing +Z\n"
      << "element vertex " << m.vertex_count << "\nproperty float x\nproperty float y\nproperty float z\n";
    if (m.normals) h << "property float nx\nproperty float ny\nproperty float nz\n";
    h << "element face " << m.triangle_count << "\nproperty list uchar uint vertex_indices\nend_header\n";
    std::string s = h.str();
    auto put = [&](const void* p, std::size_t n) { s.append(static_cast<const char*>(p), n); };
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        put(m.positions + 3 * v, 12);
        if (m.normals) put(m.normals + 3 * v, 12);
    }
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const unsigned char three = 3;
        put(&three, 1);
        put(m.triangles + 3 * t, 12);
    }
    return s;
}

void write_ply(const std::string& path, const MeshView& m) { commit(path, ply_bytes(m)); }

namespace {
std::string extension(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void check_mesh_path(const std::string& path) {
    const std::string ext = extension(path);
    if (ext != ".obj" && ext != ".ply") fail(SSC_ERROR_INVALID_ARGUMENT, "output '" + path + "': the formats are .obj (Wavefront) and .ply (Stanford)");
}

}  // namespace

std::string mesh_bytes(const std::string& path, const MeshView& mesh) {
    check_mesh_path(path);
    return extension(path) == ".obj" ? obj_bytes(mesh) : ply_bytes(mesh);
}

void write_mesh(const std::string& path, const MeshView& mesh) { commit(path, mesh_bytes(path, mesh)); }

}  // namespace ssc::exporters
