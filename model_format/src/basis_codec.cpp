#include "sscape_format/basis_codec.hpp"

#include "common/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <unordered_map>

namespace ssc::format {
namespace {

// Compressed adjacency (both directions of every polygon edge). Edges with an index out of range
// are skipped: the writer may be asked (by tests) to encode an invalid mesh, and the tree must
// still be well-formed.
struct Adjacency {
    std::vector<uint32_t> offsets, neighbours;
    Adjacency(uint32_t n, const Vec<uint32_t>& tris, const Vec<uint32_t>& quads) : offsets(n + 1, 0) {
        auto for_edges = [&](auto&& fn) {
            auto edge = [&](uint32_t a, uint32_t b) { if (a < n && b < n) fn(a, b); };
            for (std::size_t t = 0; t + 3 <= tris.size(); t += 3)
                for (int e = 0; e < 3; ++e) edge(tris[t + e], tris[t + (e + 1) % 3]);
            for (std::size_t t = 0; t + 4 <= quads.size(); t += 4)
                for (int e = 0; e < 4; ++e) edge(quads[t + e], quads[t + (e + 1) % 4]);
        };
        for_edges([&](uint32_t a, uint32_t b) { ++offsets[a + 1]; ++offsets[b + 1]; });
        for (uint32_t i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
        neighbours.resize(offsets[n]);
        std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for_edges([&](uint32_t a, uint32_t b) { neighbours[fill[a]++] = b; neighbours[fill[b]++] = a; });
        // Neighbours by index: the breadth-first order then follows the mesh's own vertex order
        // locally, which zstd's matches exploit (a tenth smaller on the default model).
        for (uint32_t v = 0; v < n; ++v) std::sort(neighbours.begin() + offsets[v], neighbours.begin() + offsets[v + 1]);
    }
};

// Breadth-first forest over the vertices `include` accepts, appended to t.
template <class Include>
void breadth_first(const Adjacency& adj, uint32_t n, const Include& include, std::vector<uint32_t>& pos, PredictionTree& t) {
    for (uint32_t root = 0; root < n; ++root) {
        if (pos[root] != kNone || !include(root)) continue;
        pos[root] = static_cast<uint32_t>(t.order.size());
        t.order.push_back(root);
        t.predictor.push_back(pos[root]);
        for (std::size_t head = pos[root]; head < t.order.size(); ++head) {
            const uint32_t v = t.order[head];
            for (uint32_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e) {
                const uint32_t w = adj.neighbours[e];
                if (pos[w] != kNone || !include(w)) continue;
                pos[w] = static_cast<uint32_t>(t.order.size());
                t.order.push_back(w);
                t.predictor.push_back(static_cast<uint32_t>(head));
            }
        }
    }
}

// Each vertex's mirror twin across x = 0 (itself when it has none): the nearest mirror image within
// tolerance, kept only when the relation is mutual. A hash grid of tolerance-sized cells.
// Vertices beyond a kilometre (or not finite: a model the writer is told not to validate) have none.
std::vector<uint32_t> mirror_twins(uint32_t n, const float* p, double tolerance) {
    auto usable = [&](uint32_t v) {
        for (int a = 0; a < 3; ++a)
            if (!(std::abs(double(p[3 * v + a])) < 1e3)) return false;
        return true;
    };
    auto cell = [&](double x) { return static_cast<int64_t>(std::floor(x / tolerance)); };
    auto key = [](int64_t x, int64_t y, int64_t z) { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); };
    std::unordered_multimap<int64_t, uint32_t> grid;
    for (uint32_t v = 0; v < n; ++v)
        if (usable(v)) grid.emplace(key(cell(p[3 * v]), cell(p[3 * v + 1]), cell(p[3 * v + 2])), v);
    std::vector<uint32_t> nearest(n);
    for (uint32_t v = 0; v < n; ++v) {
        nearest[v] = v;
        if (!usable(v)) continue;
        const double x = -double(p[3 * v]), y = p[3 * v + 1], z = p[3 * v + 2];
        double best = tolerance * tolerance;
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    const auto range = grid.equal_range(key(cell(x) + dx, cell(y) + dy, cell(z) + dz));
                    for (auto it = range.first; it != range.second; ++it) {
                        const uint32_t w = it->second;
                        const double d2 = (p[3 * w] - x) * (p[3 * w] - x) + (p[3 * w + 1] - y) * (p[3 * w + 1] - y) +
                                          (p[3 * w + 2] - z) * (p[3 * w + 2] - z);
                        if (d2 < best || (d2 == best && w < nearest[v])) best = d2, nearest[v] = w;
                    }
                }
    }
    for (uint32_t v = 0; v < n; ++v)
        if (nearest[nearest[v]] != v) nearest[v] = v;
    return nearest;
}

// Where position i's value in one row (component k, axis a) is predicted from: its tree parent p,
// and with a mirror twin m coded earlier, the twin's and the parent's twin's values (mp). A source
// that is missing points at position n, which holds 0, so every prediction is one expression
// without branches (decoding a model predicts some 2 million values).
struct Sources {
    uint32_t p, m, mp;
};
std::vector<Sources> prediction_sources(uint32_t n, const uint32_t* predictor, const uint32_t* mirror) {
    std::vector<Sources> from(n);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t p = predictor[i];
        const bool twin = mirror && mirror[i] != i;
        from[i] = {p == i ? n : p, twin ? mirror[i] : n, twin ? mirror[p] : n};
    }
    return from;
}
// The prediction from earlier positions' values (n + 1 of them, value[n] = 0): the parent's value
// plus, with a twin, sign times the twin's value less the parent's twin's.
inline int64_t prediction(const int32_t* value, const Sources& f, int64_t sign) {
    return value[f.p] + sign * (int64_t(value[f.m]) - value[f.mp]);
}

}  // namespace

PredictionTree build_prediction_tree(uint32_t n, const Vec<uint32_t>& tris, const Vec<uint32_t>& quads) {
    const Adjacency adj(n, tris, quads);
    PredictionTree t;
    t.order.reserve(n);
    t.predictor.reserve(n);
    std::vector<uint32_t> pos(n, kNone);
    breadth_first(adj, n, [](uint32_t) { return true; }, pos, t);
    return t;
}

PredictionTree build_mirror_tree(uint32_t n, const Vec<uint32_t>& tris, const Vec<uint32_t>& quads, const float* positions,
                                 double tolerance) {
    const Adjacency adj(n, tris, quads);
    const std::vector<uint32_t> twin = mirror_twins(n, positions, tolerance);
    // Of each pair, the one further to -x (or with the larger index at equal x) is coded after its twin.
    auto second = [&](uint32_t v) {
        const uint32_t w = twin[v];
        return w != v && (positions[3 * v] < positions[3 * w] || (positions[3 * v] == positions[3 * w] && v > w));
    };
    PredictionTree t;
    t.order.reserve(n);
    t.predictor.reserve(n);
    std::vector<uint32_t> pos(n, kNone);
    breadth_first(adj, n, [&](uint32_t v) { return !second(v); }, pos, t);
    const std::size_t first_side = t.order.size();
    t.mirror.resize(first_side);
    for (std::size_t i = 0; i < first_side; ++i) t.mirror[i] = static_cast<uint32_t>(i);
    for (std::size_t i = 0; i < first_side; ++i) {
        const uint32_t v = t.order[i], w = twin[v];
        if (!second(w)) continue;
        const auto at = static_cast<uint32_t>(t.order.size());
        pos[w] = at;
        t.order.push_back(w);
        const uint32_t parent = t.predictor[i];
        if (parent == i) {  // a root: predicted from its twin alone
            t.predictor.push_back(static_cast<uint32_t>(i));
            t.mirror.push_back(at);
        } else {
            const uint32_t up = t.order[parent];
            t.predictor.push_back(twin[up] != up ? pos[twin[up]] : parent);
            t.mirror.push_back(static_cast<uint32_t>(i));
        }
    }
    return t;
}

EncodedBasis encode_basis(const QuantizedBasis& b, uint32_t n, const PredictionTree& tree) {
    const std::size_t count = static_cast<std::size_t>(b.components) * 3 * n;
    const uint32_t* mirror = tree.mirror.empty() ? nullptr : tree.mirror.data();
    EncodedBasis out;
    out.planes.resize(4 * count);
    const std::vector<Sources> from = prediction_sources(n, tree.predictor.data(), mirror);
    std::vector<int32_t> value(std::size_t(n) + 1, 0);  // by position, one row at a time; value[n] stays 0
    auto row_values = [&](std::size_t row) {
        const int16_t* q = b.q.data() + row * n;
        for (uint32_t i = 0; i < n; ++i) value[i] = q[tree.order[i]];
    };
    // Each component's sign: the one whose residuals cost the fewest bits (about log2 of 1 + |r|).
    if (mirror) {
        out.signs.resize(b.components);
        for (uint32_t k = 0; k < b.components; ++k) {
            double best = 0;
            for (int s : {0, 1, -1}) {
                double bits = 0;
                for (int a = 0; a < 3; ++a) {
                    row_values(3 * std::size_t(k) + a);
                    const int sign = a == 0 ? -s : s;
                    for (uint32_t i = 0; i < n; ++i)
                        bits += std::log2(1.0 + double(std::llabs(value[i] - prediction(value.data(), from[i], sign))));
                }
                if (s == 0 || bits < best) best = bits, out.signs[k] = static_cast<int8_t>(s);
            }
        }
    }
    std::size_t at = 0;
    for (std::size_t row = 0; row < static_cast<std::size_t>(b.components) * 3; ++row) {
        row_values(row);
        const int s = mirror ? out.signs[row / 3] : 0, sign = row % 3 == 0 ? -s : s;
        for (uint32_t i = 0; i < n; ++i, ++at) {
            const auto r = static_cast<int32_t>(value[i] - prediction(value.data(), from[i], sign));
            const uint32_t z = (static_cast<uint32_t>(r) << 1) ^ static_cast<uint32_t>(r >> 31);
            for (int k = 0; k < 4; ++k) out.planes[k * count + at] = static_cast<uint8_t>(z >> (8 * k));
        }
    }
    return out;
}

void decode_residuals(const uint8_t* planes, std::size_t plane_bytes, uint32_t n, uint32_t components,
                      const uint32_t* order, const uint32_t* predictor, const uint32_t* mirror, const int8_t* signs,
                      Vec<int16_t>& q) {
    SSC_REQUIRE_MODEL((mirror == nullptr) == (signs == nullptr), "shape.mirror and shape.mirror_signs come together");
    const std::size_t count = static_cast<std::size_t>(components) * 3 * n;
    SSC_REQUIRE_MODEL(plane_bytes == 4 * count, "shape.residual_planes holds " + std::to_string(plane_bytes) +
                                                " bytes, expected " + std::to_string(4 * count));
    std::vector<uint8_t> seen(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        SSC_REQUIRE_MODEL(order[i] < n && !seen[order[i]], "shape.vertex_order is not a permutation (position " +
                                                            std::to_string(i) + ")");
        seen[order[i]] = 1;
        SSC_REQUIRE_MODEL(predictor[i] <= i, "shape.predictor[" + std::to_string(i) + "] refers forward");
        SSC_REQUIRE_MODEL(!mirror || mirror[i] == i || (mirror[i] < i && predictor[i] < i),
                          "shape.mirror[" + std::to_string(i) + "] refers forward or lacks a predictor");
    }
    for (uint32_t k = 0; signs && k < components; ++k)
        SSC_REQUIRE_MODEL(signs[k] >= -1 && signs[k] <= 1, "shape.mirror_signs[" + std::to_string(k) + "] is not -1, 0 or 1");
    q.resize(count);
    const std::vector<Sources> from = prediction_sources(n, predictor, mirror);
    std::vector<int32_t> value(std::size_t(n) + 1, 0);  // by position, one row at a time; value[n] stays 0
    std::vector<int64_t> residual(n);
    for (std::size_t row = 0; row < static_cast<std::size_t>(components) * 3; ++row) {
        // A row's residuals first, in a loop of its own (independent values: it vectorizes), then
        // the predictions, which depend on earlier positions' values.
        const uint8_t* b = planes + row * n;
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t z = uint32_t(b[i]) | uint32_t(b[count + i]) << 8 | uint32_t(b[2 * count + i]) << 16 | uint32_t(b[3 * count + i]) << 24;
            residual[i] = static_cast<int64_t>(z >> 1) ^ -static_cast<int64_t>(z & 1);
        }
        int16_t* out = q.data() + row * n;
        const int s = signs ? signs[row / 3] : 0;
        const int64_t sign = row % 3 == 0 ? -s : s;
        bool in_range = true;
        auto decode = [&](auto mirrored) {
            for (uint32_t i = 0; i < n; ++i) {
                const Sources& f = from[i];
                // (without a mirror term: prediction() with sign 0)
                const int64_t v = residual[i] + (decltype(mirrored)::value ? prediction(value.data(), f, sign) : int64_t(value[f.p]));
                in_range &= v >= -32768 && v <= 32767;
                value[i] = static_cast<int32_t>(v);
                out[order[i]] = static_cast<int16_t>(v);
            }
        };
        if (sign != 0) decode(std::true_type{});
        else decode(std::false_type{});
        SSC_REQUIRE_MODEL(in_range, "shape basis value out of 16-bit range (component " + std::to_string(row / 3) + ")");
    }
}

}  // namespace ssc::format
