#include "segments.hpp"

namespace ssc {

std::vector<SegmentSpace> build_segment_spaces(const format::ModelData& data, const Allocator* alloc) {
    const uint32_t V = data.vertex_count(), J = data.joint_count();
    const auto& sk = data.skeleton;
    std::vector<SegmentSpace> out;
    uint32_t first = 0;
    std::vector<uint32_t> local(V, format::kNone);
    for (const auto& sg : data.segments) {
        SegmentSpace s;
        s.name = sg.name;
        s.components = sg.basis.components;
        s.first = first;
        first += s.components;
        s.vertices = sg.vertices;
        s.weights = sg.weights;
        const std::size_t n = sg.vertices.size(), K = s.components;
        s.basis = Vec<float>(3 * n * K, 0.f, CAlloc<float>(alloc));
        for (std::size_t k = 0; k < K; ++k)
            for (std::size_t a = 0; a < 3; ++a)
                for (std::size_t i = 0; i < n; ++i) {
                    const std::size_t at = (k * 3 + a) * n + i;
                    s.basis[at] = sg.basis.step[k] * float(sg.basis.q[at]);
                }
        for (std::size_t i = 0; i < n; ++i) local[sg.vertices[i]] = uint32_t(i);
        s.joint_basis = Vec<float>(3ull * J * K, 0.f, CAlloc<float>(alloc));
        for (uint32_t j = 0; j < J; ++j)
            for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e) {
                const uint32_t i = local[sk.regressor_vertices[e]];
                if (i == format::kNone) continue;
                for (std::size_t k = 0; k < K; ++k)
                    for (std::size_t a = 0; a < 3; ++a)
                        s.joint_basis[(k * J + j) * 3 + a] += sk.regressor_weights[e] * s.basis[(k * 3 + a) * n + i];
            }
        for (uint32_t v : sg.vertices) local[v] = format::kNone;
        out.push_back(std::move(s));
    }
    return out;
}

void add_segment_shapes(const std::vector<SegmentSpace>& segments, uint32_t V, uint32_t J, const float* coefficients,
                        float* rest, float* joints) {
    for (const auto& s : segments) {
        const std::size_t n = s.vertices.size();
        for (uint32_t k = 0; k < s.components; ++k) {
            const float c = coefficients[s.first + k];
            if (c == 0.f) continue;  // most of a body's segment coefficients are
            for (std::size_t a = 0; a < 3; ++a) {
                const float* col = s.basis.data() + (std::size_t(k) * 3 + a) * n;
                float* r = rest + a * V;
                for (std::size_t i = 0; i < n; ++i) r[s.vertices[i]] += c * col[i];
            }
            const float* jb = s.joint_basis.data() + std::size_t(k) * 3 * J;
            for (std::size_t i = 0; i < 3ull * J; ++i) joints[i] += c * jb[i];
        }
    }
}

}  // namespace ssc
