#include "detail_levels.hpp"

#include "closest_on_mesh.hpp"
#include "common/error.hpp"
#include "makehuman/proxy.hpp"
#include "measure/measurements.hpp"

#include <Eigen/Dense>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

namespace ssc::training {
namespace fs = std::filesystem;

namespace {

using Vector3d = Eigen::Vector3d;

Vector3d at(const std::vector<float>& xyz, uint32_t v) { return Vector3d(xyz[3 * std::size_t(v)], xyz[3 * std::size_t(v) + 1], xyz[3 * std::size_t(v) + 2]); }

// The template's surface: positions, triangles, each vertex's neighbours.
struct Surface {
    const std::vector<float>& xyz;
    const std::vector<uint32_t>& triangles;
    std::vector<std::vector<uint32_t>> neighbours, vertex_triangles;
    Surface(const std::vector<float>& x, const std::vector<uint32_t>& t, uint32_t V) : xyz(x), triangles(t), neighbours(V), vertex_triangles(V) {
        for (uint32_t f = 0; 3 * std::size_t(f) < t.size(); ++f)
            for (int c = 0; c < 3; ++c) {
                const uint32_t a = t[3 * std::size_t(f) + std::size_t(c)], b = t[3 * std::size_t(f) + std::size_t((c + 1) % 3)];
                neighbours[a].push_back(b), neighbours[b].push_back(a);
                vertex_triangles[a].push_back(f);
            }
        for (auto& n : neighbours) {
            std::sort(n.begin(), n.end());
            n.erase(std::unique(n.begin(), n.end()), n.end());
        }
    }
    Vector3d corner(uint32_t f, int c) const { return at(xyz, triangles[3 * std::size_t(f) + std::size_t(c)]); }
};

// One level vertex: at most 4 body vertices and their weights (summing to 1).
struct Binding {
    std::array<uint32_t, 4> source{};
    std::array<double, 4> weight{};
};

// Binds point p near the surface point sum w_k X[corner_k]: the corners and weights, and the offset
// p minus that point folded into a fourth vertex off the triangle's plane (tetrahedral
// coordinates), so the level vertex stays a fixed affine combination of body vertices, at that
// offset on every body. Offsets under 0.01 mm are dropped; a tetrahedron too flat to hold one
// (weights past 4) drops it too.
Binding bind(const Surface& s, const Vector3d& p, const std::array<uint32_t, 3>& corner, const std::array<double, 3>& w) {
    Binding b;
    Vector3d on = Vector3d::Zero();
    for (int k = 0; k < 3; ++k) b.source[std::size_t(k)] = corner[std::size_t(k)], b.weight[std::size_t(k)] = w[std::size_t(k)], on += w[std::size_t(k)] * at(s.xyz, corner[std::size_t(k)]);
    b.source[3] = corner[0], b.weight[3] = 0;
    const Vector3d offset = p - on;
    if (offset.norm() < 1e-5 || corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2]) return b;
    const Vector3d x0 = at(s.xyz, corner[0]), x1 = at(s.xyz, corner[1]), x2 = at(s.xyz, corner[2]);
    const Vector3d n = (x1 - x0).cross(x2 - x0).normalized();
    uint32_t q = corner[0];
    double far = 0;
    for (uint32_t c : corner)
        for (uint32_t v : s.neighbours[c]) {
            if (v == corner[0] || v == corner[1] || v == corner[2]) continue;
            const double d = std::abs((at(s.xyz, v) - on).dot(n)) / std::max(1e-9, (at(s.xyz, v) - on).norm());
            if (d > far) far = d, q = v;
        }
    if (far < 0.2) return b;
    const Vector3d x3 = at(s.xyz, q);
    Eigen::Matrix4d A;
    Eigen::Vector4d rhs;
    for (int r = 0; r < 3; ++r) A(r, 0) = x0[r], A(r, 1) = x1[r], A(r, 2) = x2[r], A(r, 3) = x3[r], rhs[r] = p[r];
    A.row(3).setOnes();
    rhs[3] = 1;
    const Eigen::Vector4d l = A.fullPivLu().solve(rhs);
    if (!l.allFinite() || l.cwiseAbs().maxCoeff() > 4 || (A * l - rhs).norm() > 1e-6) return b;
    b.source[3] = q;
    for (int k = 0; k < 4; ++k) b.weight[std::size_t(k)] = l[k];
    return b;
}

// A level from its bindings, mesh and UVs: the skin (the sources' weights blended, at most 4
// influences kept and renormalised) and the landmarks (the closest point of the level's surface to
// each of the model's on the template).
format::DetailLevel make_level(const std::string& name, const format::ModelData& m, const std::vector<float>& body, const std::vector<Binding>& bindings,
                               std::vector<uint32_t> triangles, std::vector<float> uvs, std::vector<uint32_t> triangle_uvs, LevelReport* report) {
    format::DetailLevel l;
    l.name = name;
    l.vertex_count = uint32_t(bindings.size());
    std::vector<float> xyz(3 * bindings.size());
    for (std::size_t i = 0; i < bindings.size(); ++i) {
        Vector3d p = Vector3d::Zero();
        std::map<uint16_t, double> skin;
        for (std::size_t k = 0; k < 4; ++k) {
            l.sources.push_back(bindings[i].source[k]);
            l.source_weights.push_back(float(bindings[i].weight[k]));
            p += bindings[i].weight[k] * at(body, bindings[i].source[k]);
            for (std::size_t s = 0; s < 4; ++s) {
                const std::size_t slot = 4 * std::size_t(bindings[i].source[k]) + s;
                if (m.skin.weights[slot] > 0 && bindings[i].weight[k] > 0) skin[m.skin.joints[slot]] += bindings[i].weight[k] * m.skin.weights[slot];
            }
        }
        // The float weights must still sum to 1: the rounding goes to the largest.
        double sum = 0;
        for (std::size_t k = 0; k < 4; ++k) sum += l.source_weights[4 * i + k];
        const auto largest = std::max_element(l.source_weights.begin() + std::ptrdiff_t(4 * i), l.source_weights.begin() + std::ptrdiff_t(4 * i + 4));
        *largest += float(1 - sum);
        for (int a = 0; a < 3; ++a) xyz[3 * i + std::size_t(a)] = float(p[a]);
        std::vector<std::pair<double, uint16_t>> by_weight;
        for (const auto& [j, w] : skin) by_weight.emplace_back(w, j);
        std::sort(by_weight.begin(), by_weight.end(), [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
        by_weight.resize(std::min<std::size_t>(by_weight.size(), 4));
        double total = 0;
        for (const auto& [w, j] : by_weight) total += w;
        for (std::size_t s = 0; s < 4; ++s) {
            l.skin_joints.push_back(s < by_weight.size() ? by_weight[s].second : 0);
            l.skin_weights.push_back(s < by_weight.size() ? float(by_weight[s].first / total) : 0.f);
        }
        double skin_sum = 0;
        for (std::size_t s = 0; s < 4; ++s) skin_sum += l.skin_weights[4 * i + s];
        l.skin_weights[4 * i] += float(1 - skin_sum);
    }
    l.triangles = std::move(triangles);
    l.uvs = std::move(uvs);
    l.triangle_uvs = std::move(triangle_uvs);
    const MeshClosest on_level(xyz, l.triangles);
    for (uint32_t k = 0; k < m.landmarks.size(); ++k) {
        const Vector3d p = measure::landmark_position(m, k, body.data());
        const auto [f, w] = on_level(p);
        l.landmark_triangles.push_back(f);
        const float u = float(w[0]), v = float(w[1]);
        l.landmark_barycentric.insert(l.landmark_barycentric.end(), {u, v, 1.f - u - v});
    }
    if (report) {
        // How far the level's vertices lie off the body's surface on the template.
        report->name = name, report->vertices = l.vertex_count, report->triangles = l.triangle_count();
        report->offset_mean = report->offset_max = 0;
        const std::vector<uint32_t> model_triangles(m.mesh.triangles.begin(), m.mesh.triangles.end());
        const MeshClosest on_body(body, model_triangles);
        for (std::size_t i = 0; i < bindings.size(); ++i) {
            const Vector3d p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
            const auto [f, w] = on_body(p);
            Vector3d on = Vector3d::Zero();
            for (int c = 0; c < 3; ++c) on += w[std::size_t(c)] * at(body, m.mesh.triangles[3 * std::size_t(f) + std::size_t(c)]);
            const double d = (p - on).norm();
            report->offset_mean += d / double(bindings.size()), report->offset_max = std::max(report->offset_max, d);
        }
    }
    return l;
}

format::DetailLevel proxy_level(const mh::Proxy& proxy, const format::ModelData& m, const Surface& s, const std::vector<float>& body,
                                LevelReport* report) {
    const uint32_t V = m.vertex_count();
    const std::vector<std::array<double, 3>> at_body = proxy_positions(proxy, body);
    const std::vector<uint32_t> model_triangles(m.mesh.triangles.begin(), m.mesh.triangles.end());
    const MeshClosest on_body(body, model_triangles);
    std::vector<Binding> bindings;
    for (uint32_t i = 0; i < proxy.vertex_count(); ++i) {
        const Vector3d p(at_body[i][0], at_body[i][1], at_body[i][2]);
        const auto& r = proxy.refs[i];
        const auto& w = proxy.weights[i];
        if (r[0] < V && r[1] < V && r[2] < V) {
            bindings.push_back(bind(s, p, r, {w[0], w[1], w[2]}));
            continue;
        }
        // Bound to the helper geometry the model does not carry: rebound to the body's surface.
        const auto [f, bw] = on_body(p);
        bindings.push_back(bind(s, p, {model_triangles[3 * std::size_t(f)], model_triangles[3 * std::size_t(f) + 1], model_triangles[3 * std::size_t(f) + 2]}, bw));
    }
    return make_level(proxy.name, m, body, bindings, proxy.triangles, proxy.uvs, proxy.triangle_uvs, report);
}

// The template simplified by meshoptimizer to about `target` vertices. Corners are (vertex, UV)
// pairs, so the simplifier sees the UV seams and keeps them; each kept corner is a body vertex.
format::DetailLevel simplified_level(const format::ModelData& m, const std::vector<float>& body, uint32_t target, LevelReport* report) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> corner_id;
    std::vector<std::pair<uint32_t, uint32_t>> corners;
    std::vector<unsigned int> indices;
    const bool with_uvs = !m.mesh.uvs.empty();
    for (std::size_t i = 0; i < m.mesh.triangles.size(); ++i) {
        const std::pair<uint32_t, uint32_t> c{m.mesh.triangles[i], with_uvs ? m.mesh.triangle_uvs[i] : 0};
        const auto [it, added] = corner_id.emplace(c, uint32_t(corners.size()));
        if (added) corners.push_back(c);
        indices.push_back(it->second);
    }
    std::vector<float> positions;
    for (const auto& [v, t] : corners)
        for (int a = 0; a < 3; ++a) positions.push_back(body[3 * std::size_t(v) + std::size_t(a)]);
    auto simplify = [&](std::size_t target_indices, std::vector<unsigned int>& out) {
        out.resize(indices.size());
        float error = 0;
        out.resize(meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(), corners.size(), 3 * sizeof(float), target_indices,
                                    0.05f, 0, &error));
    };
    auto vertices_of = [&](const std::vector<unsigned int>& idx) {
        std::set<uint32_t> used;
        for (unsigned int i : idx) used.insert(corners[i].first);
        return used.size();
    };
    // The simplifier targets indices; search the index count whose result has about `target` vertices.
    std::size_t lo = 3, hi = indices.size();
    std::vector<unsigned int> out;
    for (int step = 0; step < 16 && hi - lo > 30; ++step) {
        const std::size_t mid = (lo + hi) / 2 / 3 * 3;
        simplify(mid, out);
        (vertices_of(out) < target ? lo : hi) = mid;
    }
    simplify(hi, out);
    meshopt_optimizeVertexCache(out.data(), out.data(), out.size(), corners.size());
    std::map<uint32_t, uint32_t> vertex_index, uv_index;
    std::vector<Binding> bindings;
    std::vector<uint32_t> triangles, triangle_uvs;
    std::vector<float> uvs;
    for (unsigned int i : out) {
        const auto [v, t] = corners[i];
        const auto [vi, new_vertex] = vertex_index.emplace(v, uint32_t(bindings.size()));
        if (new_vertex) {
            Binding b;
            b.source = {v, v, v, v};
            b.weight = {1, 0, 0, 0};
            bindings.push_back(b);
        }
        triangles.push_back(vi->second);
        if (with_uvs) {
            const auto [ti, new_uv] = uv_index.emplace(t, uint32_t(uvs.size() / 2));
            if (new_uv) uvs.insert(uvs.end(), {m.mesh.uvs[2 * std::size_t(t)], m.mesh.uvs[2 * std::size_t(t) + 1]});
            triangle_uvs.push_back(ti->second);
        }
    }
    return make_level("simplified", m, body, bindings, std::move(triangles), std::move(uvs), std::move(triangle_uvs), report);
}

}  // namespace

std::vector<format::DetailLevel> make_detail_levels(const mh::Assets& assets, const format::ModelData& m, const std::vector<float>& body,
                                                    const LevelSpec& spec, std::vector<LevelReport>* report) {
    SSC_REQUIRE_ARG(body.size() >= 3ull * m.vertex_count(), "make_detail_levels: the body needs every model vertex");
    const std::vector<uint32_t> model_triangles(m.mesh.triangles.begin(), m.mesh.triangles.end());
    const Surface s(body, model_triangles, m.vertex_count());
    std::vector<format::DetailLevel> levels;
    if (report) report->clear();
    auto next_report = [&]() -> LevelReport* { return report ? &report->emplace_back() : nullptr; };
    if (spec.simplified_vertices > 0) levels.push_back(simplified_level(m, body, spec.simplified_vertices, next_report()));
    const uint32_t base_vertices = uint32_t(body.size() / 3);
    for (const std::string& name : spec.proxies) {
        const fs::path path = fs::path(assets.root) / "makehuman-assets" / "base" / "proxymeshes" / name / (name + ".proxy");
        levels.push_back(proxy_level(mh::read_proxy(path.string(), base_vertices), m, s, body, next_report()));
    }
    return levels;
}

}  // namespace ssc::training
