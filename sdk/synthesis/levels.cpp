#include "levels.hpp"

#include <cmath>

namespace ssc {

LevelTopology::LevelTopology(const format::DetailLevel& level) {
    const uint32_t N = level.vertex_count;
    vertex_triangle_offsets.assign(N + 1, 0);
    for (uint32_t v : level.triangles) ++vertex_triangle_offsets[v + 1];
    for (uint32_t v = 0; v < N; ++v) vertex_triangle_offsets[v + 1] += vertex_triangle_offsets[v];
    vertex_triangles.resize(level.triangles.size());
    std::vector<uint32_t> fill(vertex_triangle_offsets.begin(), vertex_triangle_offsets.end() - 1);
    for (uint32_t i = 0; i < level.triangles.size(); ++i) vertex_triangles[fill[level.triangles[i]]++] = i / 3;
}

namespace levels {

void from_body(const format::DetailLevel& level, const float* body_planar, uint32_t V, float* out_planar) {
    const uint32_t N = level.vertex_count;
    const uint32_t* src = level.sources.data();
    const float* w = level.source_weights.data();
    for (uint32_t i = 0; i < N; ++i, src += 4, w += 4)
        for (uint32_t a = 0; a < 3; ++a) {
            const float* block = body_planar + std::size_t(a) * V;
            out_planar[std::size_t(a) * N + i] = w[0] * block[src[0]] + w[1] * block[src[1]] + w[2] * block[src[2]] + w[3] * block[src[3]];
        }
}

void normals(const format::DetailLevel& level, const LevelTopology& topology, const float* planar, float* face_scratch, float* out_xyz) {
    const std::vector<uint32_t>& t = level.triangles;
    const std::size_t N = level.vertex_count;
    const float *X = planar, *Y = planar + N, *Z = planar + 2 * N;
    for (std::size_t f = 0; 3 * f < t.size(); ++f) {
        const uint32_t a = t[3 * f], b = t[3 * f + 1], c = t[3 * f + 2];
        const float e1[3] = {X[b] - X[a], Y[b] - Y[a], Z[b] - Z[a]}, e2[3] = {X[c] - X[a], Y[c] - Y[a], Z[c] - Z[a]};
        face_scratch[3 * f] = e1[1] * e2[2] - e1[2] * e2[1];
        face_scratch[3 * f + 1] = e1[2] * e2[0] - e1[0] * e2[2];
        face_scratch[3 * f + 2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
    for (uint32_t v = 0; v < level.vertex_count; ++v) {
        float n[3] = {0, 0, 0};
        for (uint32_t k = topology.vertex_triangle_offsets[v]; k < topology.vertex_triangle_offsets[v + 1]; ++k)
            for (int e = 0; e < 3; ++e) n[e] += face_scratch[3 * std::size_t(topology.vertex_triangles[k]) + std::size_t(e)];
        const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const float s = len > 0 ? 1 / len : 0;
        for (int e = 0; e < 3; ++e) out_xyz[3 * std::size_t(v) + std::size_t(e)] = n[e] * s;
    }
}

}  // namespace levels
}  // namespace ssc
