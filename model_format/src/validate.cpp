// Semantic validation: everything the FlatBuffers verifier cannot know. After this passes, the
// runtime may index every array without further checks.
#include "common/error.hpp"
#include "sscape_format/model_data.hpp"

#include <cmath>
#include <set>
#include <string>

namespace ssc::format {
namespace {

template <class V>
void require_size(const V& v, std::size_t expected, const char* what) {
    SSC_REQUIRE_MODEL(v.size() == expected, std::string(what) + " has " + std::to_string(v.size()) +
                                            " values, expected " + std::to_string(expected));
}

template <class V>
void require_finite(const V& v, const char* what) {
    for (std::size_t i = 0; i < v.size(); ++i)
        SSC_REQUIRE_MODEL(std::isfinite(v[i]), std::string(what) + "[" + std::to_string(i) + "] is not finite");
}

template <class V>
void require_below(const V& v, uint64_t limit, const char* what) {
    for (std::size_t i = 0; i < v.size(); ++i)
        SSC_REQUIRE_MODEL(v[i] < limit, std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(v[i]) +
                                        " is out of range (< " + std::to_string(limit) + ")");
}

void require_unique_names(const std::vector<std::string>& names, const char* what) {
    std::set<std::string> seen;
    for (const auto& n : names) {
        SSC_REQUIRE_MODEL(!n.empty(), std::string(what) + " has an empty name");
        SSC_REQUIRE_MODEL(seen.insert(n).second, std::string(what) + " repeats the name '" + n + "'");
    }
}

}  // namespace

void validate_model(const ModelData& m) {
    const uint32_t V = m.mesh.vertex_count;
    SSC_REQUIRE_MODEL(V >= 3, "mesh.vertex_count must be at least 3");

    // Mesh.
    const auto& mesh = m.mesh;
    SSC_REQUIRE_MODEL(!mesh.triangles.empty() && mesh.triangles.size() % 3 == 0, "mesh.triangles must hold 3 indices per triangle");
    SSC_REQUIRE_MODEL(mesh.quads.size() % 4 == 0, "mesh.quads must hold 4 indices per quad");
    require_below(mesh.triangles, V, "mesh.triangles");
    require_below(mesh.quads, V, "mesh.quads");
    SSC_REQUIRE_MODEL(mesh.uvs.size() % 2 == 0, "mesh.uvs must hold 2 floats per coordinate");
    require_finite(mesh.uvs, "mesh.uvs");
    if (mesh.uvs.empty()) {
        SSC_REQUIRE_MODEL(mesh.triangle_uvs.empty() && mesh.quad_uvs.empty(), "mesh has UV indices but no UVs");
    } else {
        require_size(mesh.triangle_uvs, mesh.triangles.size(), "mesh.triangle_uvs");
        SSC_REQUIRE_MODEL(mesh.quad_uvs.empty() || mesh.quad_uvs.size() == mesh.quads.size(),
                      "mesh.quad_uvs must be empty or match mesh.quads");
        require_below(mesh.triangle_uvs, mesh.uvs.size() / 2, "mesh.triangle_uvs");
        require_below(mesh.quad_uvs, mesh.uvs.size() / 2, "mesh.quad_uvs");
    }
    SSC_REQUIRE_MODEL(uint64_t(mesh.triangles.size() / 3) < (1ull << 32), "too many triangles");  // (always true where size_t has 32 bits)

    // Shape space.
    const auto& s = m.shape;
    const uint32_t K = s.basis.components;
    require_size(s.mean, 3ull * V, "shape.mean");
    require_finite(s.mean, "shape.mean");
    require_size(s.stddev, K, "shape.stddev");
    require_size(s.basis.step, K, "shape.step");
    require_size(s.basis.q, 3ull * V * K, "shape basis");
    for (uint32_t k = 0; k < K; ++k) {
        SSC_REQUIRE_MODEL(std::isfinite(s.stddev[k]) && s.stddev[k] > 0, "shape.stddev[" + std::to_string(k) + "] must be finite and > 0");
        SSC_REQUIRE_MODEL(std::isfinite(s.basis.step[k]) && s.basis.step[k] > 0, "shape.step[" + std::to_string(k) + "] must be finite and > 0");
    }

    // Skeleton.
    const auto& sk = m.skeleton;
    const std::size_t J = sk.parents.size();
    SSC_REQUIRE_MODEL(J >= 1 && J <= 65535, "skeleton must have 1 to 65535 joints");
    require_size(sk.joint_names, J, "skeleton.joint_names");
    require_unique_names(sk.joint_names, "skeleton.joint_names");
    SSC_REQUIRE_MODEL(sk.parents[0] == -1, "skeleton.parents[0] must be -1 (the root comes first)");
    for (std::size_t j = 1; j < J; ++j)
        SSC_REQUIRE_MODEL(sk.parents[j] >= 0 && std::size_t(sk.parents[j]) < j,
                      "skeleton.parents[" + std::to_string(j) + "] must name an earlier joint");
    require_size(sk.rest_orientations, 4 * J, "skeleton.rest_orientations");
    require_finite(sk.rest_orientations, "skeleton.rest_orientations");
    for (std::size_t j = 0; j < J; ++j) {
        const float* q = &sk.rest_orientations[4 * j];
        const double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
        SSC_REQUIRE_MODEL(std::abs(n - 1.0) < 1e-3, "skeleton.rest_orientations[" + std::to_string(j) + "] is not a unit quaternion");
    }
    require_size(sk.regressor_offsets, J + 1, "skeleton.regressor_offsets");
    SSC_REQUIRE_MODEL(sk.regressor_offsets[0] == 0, "skeleton.regressor_offsets[0] must be 0");
    for (std::size_t j = 0; j < J; ++j)
        SSC_REQUIRE_MODEL(sk.regressor_offsets[j] < sk.regressor_offsets[j + 1],
                      "skeleton regressor of joint " + std::to_string(j) + " is empty or offsets decrease");
    require_size(sk.regressor_vertices, sk.regressor_offsets[J], "skeleton.regressor_vertices");
    require_size(sk.regressor_weights, sk.regressor_offsets[J], "skeleton.regressor_weights");
    require_below(sk.regressor_vertices, V, "skeleton.regressor_vertices");
    require_finite(sk.regressor_weights, "skeleton.regressor_weights");
    for (std::size_t j = 0; j < J; ++j) {
        double sum = 0;
        for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e) sum += sk.regressor_weights[e];
        // Weights summing to 1 make joints move with the body under translation.
        SSC_REQUIRE_MODEL(std::abs(sum - 1.0) < 1e-3, "skeleton regressor weights of joint " + std::to_string(j) +
                                                      " sum to " + std::to_string(sum) + ", not 1");
    }

    // Skin.
    require_size(m.skin.joints, 4ull * V, "skin.joints");
    require_size(m.skin.weights, 4ull * V, "skin.weights");
    require_below(m.skin.joints, J, "skin.joints");
    for (uint32_t v = 0; v < V; ++v) {
        double sum = 0;
        for (int i = 0; i < 4; ++i) {
            const float w = m.skin.weights[4 * v + i];
            SSC_REQUIRE_MODEL(std::isfinite(w) && w >= 0, "skin.weights of vertex " + std::to_string(v) + " must be finite and >= 0");
            sum += w;
        }
        SSC_REQUIRE_MODEL(std::abs(sum - 1.0) < 1e-3, "skin.weights of vertex " + std::to_string(v) + " sum to " +
                                                      std::to_string(sum) + ", not 1");
    }

    // Landmarks and vertex sets.
    std::vector<std::string> names;
    const uint64_t T = mesh.triangles.size() / 3;
    for (const auto& l : m.landmarks) {
        names.push_back(l.name);
        const bool on_vertex = l.vertex != kNone, on_triangle = l.triangle != kNone;
        SSC_REQUIRE_MODEL(on_vertex != on_triangle, "landmark '" + l.name + "' must name exactly one of vertex or triangle");
        if (on_vertex) {
            SSC_REQUIRE_MODEL(l.vertex < V, "landmark '" + l.name + "' vertex out of range");
        } else {
            SSC_REQUIRE_MODEL(l.triangle < T, "landmark '" + l.name + "' triangle out of range");
            double sum = 0;
            for (float b : l.barycentric) {
                SSC_REQUIRE_MODEL(std::isfinite(b), "landmark '" + l.name + "' barycentric is not finite");
                sum += b;
            }
            SSC_REQUIRE_MODEL(std::abs(sum - 1.0) < 1e-3, "landmark '" + l.name + "' barycentric weights do not sum to 1");
        }
    }
    require_unique_names(names, "landmarks");
    names.clear();
    for (const auto& set : m.vertex_sets) {
        names.push_back(set.name);
        require_below(set.vertices, V, ("vertex set '" + set.name + "'").c_str());
        for (std::size_t i = 1; i < set.vertices.size(); ++i)
            SSC_REQUIRE_MODEL(set.vertices[i - 1] < set.vertices[i], "vertex set '" + set.name + "' is not sorted and unique");
    }
    require_unique_names(names, "vertex_sets");

    // Joint limits: one per joint at most, a rotation frame, finite ordered bounds.
    for (std::size_t i = 0; i < m.joint_limits.size(); ++i) {
        const JointLimit& l = m.joint_limits[i];
        const std::string what = "joint limit " + std::to_string(i);
        SSC_REQUIRE_MODEL(l.joint < J, what + ": joint out of range");
        SSC_REQUIRE_MODEL(i == 0 || m.joint_limits[i - 1].joint < l.joint, what + ": joints must be sorted and unique");
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                double dot = 0;
                for (int k = 0; k < 3; ++k) dot += double(l.frame[3 * r + k]) * l.frame[3 * c + k];
                SSC_REQUIRE_MODEL(std::isfinite(dot) && std::abs(dot - (r == c ? 1.0 : 0.0)) < 1e-3, what + ": frame is not a rotation");
            }
        for (int a = 0; a < 3; ++a)
            SSC_REQUIRE_MODEL(std::isfinite(l.lower[a]) && std::isfinite(l.upper[a]) && l.lower[a] <= l.upper[a] &&
                                  std::abs(l.lower[a]) <= 2 * M_PI && std::abs(l.upper[a]) <= 2 * M_PI,
                              what + ": bounds must be finite, ordered and within one turn");
    }

    // Joint roles: one per joint; a limb (arm or leg, left or right) has both its joints or none,
    // the middle one below the upper one.
    if (!m.joint_roles.empty()) {
        SSC_REQUIRE_MODEL(m.joint_roles.size() == J, "joint_roles must hold one role per joint");
        int limb[2][2][2];  // [arm, leg][left, right][upper, middle]: the joint, or -1
        for (auto& a : limb)
            for (auto& b : a) b[0] = b[1] = -1;
        for (uint32_t j = 0; j < J; ++j) {
            const JointRole& r = m.joint_roles[j];
            const std::string what = "joint role " + std::to_string(j);
            SSC_REQUIRE_MODEL(r.part <= 5 && r.side <= 2 && r.limb_joint <= 2, what + ": part, side or limb_joint out of range");
            SSC_REQUIRE_MODEL(std::isfinite(r.rotation_sigma) && r.rotation_sigma > 0 && r.rotation_sigma <= 2 * M_PI,
                              what + ": rotation_sigma must be in (0, 2 pi] radians");
            if (r.limb_joint == 0) continue;
            SSC_REQUIRE_MODEL((r.part == 2 || r.part == 4) && r.side != 0, what + ": a limb joint must be of a left or right arm or leg");
            int& slot = limb[r.part == 4][r.side - 1][r.limb_joint - 1];
            SSC_REQUIRE_MODEL(slot < 0, what + ": its limb already has that joint");
            slot = int(j);
        }
        for (auto& a : limb)
            for (auto& b : a) {
                SSC_REQUIRE_MODEL((b[0] < 0) == (b[1] < 0), "joint_roles: a limb needs both its upper and middle joint, or neither");
                int up = b[1];
                while (up > b[0]) up = m.skeleton.parents[std::size_t(up)];
                SSC_REQUIRE_MODEL(up == b[0], "joint_roles: a limb's middle joint must lie below its upper joint");
            }
    }

    // Attributes: named, finite, a symmetric covariance with a positive diagonal.
    const auto& am = m.attributes;
    const std::size_t A = am.attributes.size();
    names.clear();
    for (const auto& a : am.attributes) {
        names.push_back(a.name);
        SSC_REQUIRE_MODEL(std::isfinite(a.mean) && std::isfinite(a.minimum) && std::isfinite(a.maximum) && a.minimum <= a.maximum,
                          "attribute '" + a.name + "' needs a finite mean and an ordered range");
    }
    require_unique_names(names, "attributes");
    require_size(am.covariance, A * A, "attributes.covariance");
    require_size(am.shape_covariance, A * K, "attributes.shape_covariance");
    require_finite(am.covariance, "attributes.covariance");
    require_finite(am.shape_covariance, "attributes.shape_covariance");
    for (std::size_t a = 0; a < A; ++a) {
        SSC_REQUIRE_MODEL(am.covariance[a * A + a] > 0, "attributes.covariance has a diagonal entry <= 0");
        for (std::size_t b = 0; b < a; ++b)
            SSC_REQUIRE_MODEL(am.covariance[a * A + b] == am.covariance[b * A + a], "attributes.covariance is not symmetric");
    }

    // Segment shape spaces: each a valid shape space over its own vertices; blend weights in [0, 1]
    // that sum to at most 1 at every vertex (a partition of the body, blurred at the borders).
    names.clear();
    std::vector<float> weight_sum(m.segments.empty() ? 0 : V, 0.f);
    for (const auto& sg : m.segments) {
        names.push_back(sg.name);
        const std::string what = "segment '" + sg.name + "'";
        const std::size_t n = sg.vertices.size(), Ks = sg.basis.components;
        SSC_REQUIRE_MODEL(n > 0, what + " has no vertices");
        require_below(sg.vertices, V, (what + ".vertices").c_str());
        for (std::size_t i = 1; i < n; ++i)
            SSC_REQUIRE_MODEL(sg.vertices[i - 1] < sg.vertices[i], what + ": vertices must be sorted and unique");
        require_size(sg.weights, n, (what + ".weights").c_str());
        SSC_REQUIRE_MODEL(Ks > 0, what + " has no components");
        require_size(sg.stddev, Ks, (what + ".stddev").c_str());
        require_size(sg.basis.step, Ks, (what + ".step").c_str());
        require_size(sg.basis.q, 3 * n * Ks, (what + " basis").c_str());
        for (std::size_t k = 0; k < Ks; ++k)
            SSC_REQUIRE_MODEL(std::isfinite(sg.stddev[k]) && sg.stddev[k] > 0 && std::isfinite(sg.basis.step[k]) && sg.basis.step[k] > 0,
                              what + ": stddev and step must be finite and > 0");
        for (std::size_t i = 0; i < n; ++i) {
            const float w = sg.weights[i];
            SSC_REQUIRE_MODEL(std::isfinite(w) && w >= 0 && w <= 1, what + ": weights must lie in [0, 1]");
            weight_sum[sg.vertices[i]] += w;
        }
    }
    require_unique_names(names, "segments");
    for (uint32_t v = 0; v < weight_sum.size(); ++v)
        SSC_REQUIRE_MODEL(weight_sum[v] <= 1.001f, "segments: the blend weights of vertex " + std::to_string(v) + " sum to over 1");

    // Levels of detail: each vertex an affine combination of body vertices (weights summing to 1,
    // bounded: a level vertex lies near the body vertices it is made of), its own mesh, skin and
    // landmarks.
    names.clear();
    for (const auto& lv : m.levels) {
        names.push_back(lv.name);
        const std::string what = "level '" + lv.name + "'";
        const uint64_t N = lv.vertex_count;
        SSC_REQUIRE_MODEL(!lv.name.empty(), "levels: a level has no name");
        SSC_REQUIRE_MODEL(N >= 3, what + " has fewer than 3 vertices");
        require_size(lv.sources, 4 * N, (what + ".sources").c_str());
        require_size(lv.source_weights, 4 * N, (what + ".source_weights").c_str());
        require_below(lv.sources, V, (what + ".sources").c_str());
        SSC_REQUIRE_MODEL(!lv.triangles.empty() && lv.triangles.size() % 3 == 0, what + ".triangles must hold 3 indices per triangle");
        require_below(lv.triangles, N, (what + ".triangles").c_str());
        if (!lv.uvs.empty() || !lv.triangle_uvs.empty()) {
            SSC_REQUIRE_MODEL(lv.uvs.size() % 2 == 0, what + ".uvs must hold 2 floats per coordinate");
            require_finite(lv.uvs, (what + ".uvs").c_str());
            require_size(lv.triangle_uvs, lv.triangles.size(), (what + ".triangle_uvs").c_str());
            require_below(lv.triangle_uvs, lv.uvs.size() / 2, (what + ".triangle_uvs").c_str());
        }
        require_size(lv.skin_joints, 4 * N, (what + ".skin_joints").c_str());
        require_size(lv.skin_weights, 4 * N, (what + ".skin_weights").c_str());
        require_below(lv.skin_joints, J, (what + ".skin_joints").c_str());
        for (uint64_t v = 0; v < N; ++v) {
            double source_sum = 0, skin_sum = 0;
            for (uint64_t i = 0; i < 4; ++i) {
                const float w = lv.source_weights[4 * v + i], s = lv.skin_weights[4 * v + i];
                SSC_REQUIRE_MODEL(std::isfinite(w) && std::abs(w) <= 8, what + ": source weights of vertex " + std::to_string(v) + " must be finite and within 8");
                SSC_REQUIRE_MODEL(std::isfinite(s) && s >= 0, what + ": skin weights of vertex " + std::to_string(v) + " must be finite and >= 0");
                source_sum += w, skin_sum += s;
            }
            SSC_REQUIRE_MODEL(std::abs(source_sum - 1.0) < 1e-3, what + ": source weights of vertex " + std::to_string(v) + " do not sum to 1");
            SSC_REQUIRE_MODEL(std::abs(skin_sum - 1.0) < 1e-3, what + ": skin weights of vertex " + std::to_string(v) + " do not sum to 1");
        }
        require_size(lv.landmark_triangles, m.landmarks.size(), (what + ".landmark_triangles").c_str());
        require_size(lv.landmark_barycentric, 3 * m.landmarks.size(), (what + ".landmark_barycentric").c_str());
        require_below(lv.landmark_triangles, lv.triangles.size() / 3, (what + ".landmark_triangles").c_str());
        for (std::size_t l = 0; l < m.landmarks.size(); ++l) {
            const float* b = &lv.landmark_barycentric[3 * l];
            SSC_REQUIRE_MODEL(std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && std::abs(b[0] + b[1] + b[2] - 1.0) < 1e-3,
                              what + ": landmark " + std::to_string(l) + "'s barycentric weights must be finite and sum to 1");
        }
    }
    require_unique_names(names, "levels");

    SSC_REQUIRE_MODEL(!m.metadata.units.empty() && m.metadata.units == "m", "metadata.units must be \"m\"");
}

}  // namespace ssc::format
