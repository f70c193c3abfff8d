#include "sscape_format/basis_codec.hpp"

#include "common/error.hpp"

#include <string>

namespace ssc::format {

PredictionTree build_prediction_tree(uint32_t n, const Vec<uint32_t>& tris, const Vec<uint32_t>& quads) {
    // Compressed adjacency (both directions of every polygon edge).
    std::vector<uint32_t> degree(n + 1, 0);
    // Edges with an index out of range are skipped: the writer may be asked (by tests) to encode
    // an invalid mesh, and the tree must still be well-formed.
    auto for_edges = [&](auto&& fn) {
        auto edge = [&](uint32_t a, uint32_t b) { if (a < n && b < n) fn(a, b); };
        for (std::size_t t = 0; t + 3 <= tris.size(); t += 3)
            for (int e = 0; e < 3; ++e) edge(tris[t + e], tris[t + (e + 1) % 3]);
        for (std::size_t t = 0; t + 4 <= quads.size(); t += 4)
            for (int e = 0; e < 4; ++e) edge(quads[t + e], quads[t + (e + 1) % 4]);
    };
    for_edges([&](uint32_t a, uint32_t b) { ++degree[a + 1]; ++degree[b + 1]; });
    for (uint32_t i = 0; i < n; ++i) degree[i + 1] += degree[i];
    std::vector<uint32_t> adj(degree[n]), fill(degree.begin(), degree.end() - 1);
    for_edges([&](uint32_t a, uint32_t b) { adj[fill[a]++] = b; adj[fill[b]++] = a; });

    PredictionTree t;
    t.order.reserve(n);
    t.predictor.reserve(n);
    std::vector<uint32_t> pos(n, kNone);
    for (uint32_t root = 0; root < n; ++root) {
        if (pos[root] != kNone) continue;
        pos[root] = static_cast<uint32_t>(t.order.size());
        t.order.push_back(root);
        t.predictor.push_back(pos[root]);
        for (std::size_t head = pos[root]; head < t.order.size(); ++head) {
            const uint32_t v = t.order[head];
            for (uint32_t e = degree[v]; e < degree[v + 1]; ++e) {
                const uint32_t w = adj[e];
                if (pos[w] != kNone) continue;
                pos[w] = static_cast<uint32_t>(t.order.size());
                t.order.push_back(w);
                t.predictor.push_back(static_cast<uint32_t>(head));
            }
        }
    }
    return t;
}

std::vector<uint8_t> encode_residuals(const QuantizedBasis& b, uint32_t n, const PredictionTree& tree) {
    const std::size_t count = static_cast<std::size_t>(b.components) * 3 * n;
    std::vector<uint8_t> planes(4 * count);
    std::size_t out = 0;
    for (std::size_t row = 0; row < static_cast<std::size_t>(b.components) * 3; ++row) {
        const int16_t* q = b.q.data() + row * n;
        for (uint32_t i = 0; i < n; ++i, ++out) {
            const uint32_t p = tree.predictor[i];
            const int32_t r = int32_t(q[tree.order[i]]) - (p == i ? 0 : int32_t(q[tree.order[p]]));
            const uint32_t z = (static_cast<uint32_t>(r) << 1) ^ static_cast<uint32_t>(r >> 31);
            for (int k = 0; k < 4; ++k) planes[k * count + out] = static_cast<uint8_t>(z >> (8 * k));
        }
    }
    return planes;
}

void decode_residuals(const uint8_t* planes, std::size_t plane_bytes, uint32_t n, uint32_t components,
                      const uint32_t* order, const uint32_t* predictor, Vec<int16_t>& q) {
    const std::size_t count = static_cast<std::size_t>(components) * 3 * n;
    SSC_REQUIRE_MODEL(plane_bytes == 4 * count, "shape.residual_planes holds " + std::to_string(plane_bytes) +
                                                " bytes, expected " + std::to_string(4 * count));
    std::vector<uint8_t> seen(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        SSC_REQUIRE_MODEL(order[i] < n && !seen[order[i]], "shape.vertex_order is not a permutation (position " +
                                                            std::to_string(i) + ")");
        seen[order[i]] = 1;
        SSC_REQUIRE_MODEL(predictor[i] <= i, "shape.predictor[" + std::to_string(i) + "] refers forward");
    }
    q.resize(count);
    std::vector<int32_t> value(n);  // by position, one row at a time
    std::size_t in = 0;
    for (std::size_t row = 0; row < static_cast<std::size_t>(components) * 3; ++row) {
        int16_t* out = q.data() + row * n;
        for (uint32_t i = 0; i < n; ++i, ++in) {
            const uint32_t z = uint32_t(planes[in]) | uint32_t(planes[count + in]) << 8 |
                               uint32_t(planes[2 * count + in]) << 16 | uint32_t(planes[3 * count + in]) << 24;
            const int64_t r = static_cast<int64_t>(z >> 1) ^ -static_cast<int64_t>(z & 1);
            const uint32_t p = predictor[i];
            const int64_t v = r + (p == i ? 0 : value[p]);
            SSC_REQUIRE_MODEL(v >= -32768 && v <= 32767, "shape basis value out of 16-bit range (component " +
                                                         std::to_string(row / 3) + ")");
            value[i] = static_cast<int32_t>(v);
            out[order[i]] = static_cast<int16_t>(v);
        }
    }
}

}  // namespace ssc::format
