// MakeHuman proxy meshes (shared/makehuman README, "Proxies"): a lower-resolution mesh whose every
// vertex is bound to the base mesh, as three base vertices' weighted sum plus an offset that the
// body's size scales. Read here into plain arrays; detail_levels.hpp binds them to the model.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ssc::training::mh {

struct Proxy {
    std::string name;
    // Per proxy vertex: three base-mesh vertices and their weights (a vertex bound to one base
    // vertex has it three times, weights 1 0 0), and the offset in the file's units (decimetres).
    std::vector<std::array<uint32_t, 3>> refs;
    std::vector<std::array<float, 3>> weights, offsets;
    // The offset's scale per axis x, y, z: the distance of two base vertices along that axis over a
    // reference length (decimetres).
    std::array<uint32_t, 3> scale_a{}, scale_b{};
    std::array<float, 3> scale_length{1, 1, 1};
    // The proxy's own mesh (its .obj): triangles (quads split), face-varying UVs.
    std::vector<uint32_t> triangles, triangle_uvs;
    std::vector<float> uvs;
    uint32_t vertex_count() const { return static_cast<uint32_t>(refs.size()); }
};

// Reads NAME.proxy and the .obj it names, beside it. Throws ssc::Error(SSC_ERROR_IO) naming the
// file and line on anything malformed (an index past the base mesh's base_vertex_count included).
Proxy read_proxy(const std::string& proxy_path, uint32_t base_vertex_count);

// Where each proxy vertex lies on a body (every base vertex, helpers included, metres).
std::vector<std::array<double, 3>> proxy_positions(const Proxy& proxy, const std::vector<float>& base_xyz);

}  // namespace ssc::training::mh
