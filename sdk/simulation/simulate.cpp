#include "simulation/simulate.hpp"

#include "anatomy/joint_limits.hpp"
#include "common/error.hpp"
#include "common/rigid.hpp"
#include "fitting/posed_surface.hpp"
#include "registration/registration_quality.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>

namespace ssc::simulation {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

std::vector<float> random_shape(const Model& m, std::mt19937& rng) {
    std::normal_distribution<float> n(0.f, 1.f);
    std::vector<float> c(m.component_count());
    for (auto& x : c) x = std::clamp(n(rng), -2.5f, 2.5f);
    return c;
}

namespace {

struct JointRange {
    const char* name;
    // Rotation ranges (radians) about the body's x (left), y (up) and z (forward) axes, at rest.
    double x_lo, x_hi, y_lo, y_hi, z_lo, z_hi;
};

// Everyday ranges, well inside the anatomical limits. Signs: +x bends the trunk forward, -x swings a
// thigh or upper arm forward, +x bends a knee, -x an elbow; +z raises the left arm sideways.
const JointRange kRanges[] = {
    {"spine_01", -0.05, 0.20, -0.10, 0.10, -0.06, 0.06},
    {"spine_02", -0.05, 0.20, -0.10, 0.10, -0.06, 0.06},
    {"spine_03", -0.05, 0.15, -0.10, 0.10, -0.06, 0.06},
    {"neck_01", -0.15, 0.25, -0.30, 0.30, -0.10, 0.10},
    {"head", -0.10, 0.15, -0.20, 0.20, -0.10, 0.10},
    {"upperarm_l", -0.90, 0.40, -0.30, 0.30, -0.40, 0.80},
    {"upperarm_r", -0.90, 0.40, -0.30, 0.30, -0.80, 0.40},
    {"lowerarm_l", -1.60, -0.05, -0.20, 0.20, 0, 0},  // anatomical: flexion, forearm rotation
    {"lowerarm_r", -1.60, -0.05, -0.20, 0.20, 0, 0},
    {"hand_l", -0.30, 0.30, -0.20, 0.20, -0.20, 0.20},
    {"hand_r", -0.30, 0.30, -0.20, 0.20, -0.20, 0.20},
    {"thigh_l", -0.80, 0.25, -0.20, 0.20, -0.05, 0.35},
    {"thigh_r", -0.80, 0.25, -0.20, 0.20, -0.35, 0.05},
    {"calf_l", 0.05, 1.30, 0, 0, 0, 0},
    {"calf_r", 0.05, 1.30, 0, 0, 0, 0},
    {"foot_l", -0.30, 0.30, -0.10, 0.10, -0.10, 0.10},
    {"foot_r", -0.30, 0.30, -0.10, 0.10, -0.10, 0.10},
};

}  // namespace

std::vector<float> scanning_pose(const Model& m, std::mt19937& rng, double spread) {
    const uint32_t J = m.joint_count();
    std::vector<float> q(4 * std::size_t(J), 0.f);
    for (uint32_t j = 0; j < J; ++j) q[4 * j + 3] = 1.f;
    const auto limits = anatomy::joint_limits(m);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double rad = spread * M_PI / 180;
    struct Part {
        const char* joint;
        Vector3d amount;  // flexion, axial, abduction: the share of `spread` each may reach
        bool one_sided;   // abduction only outwards (feet apart)
    };
    const Part parts[] = {{"upperarm_l", {0, 0, 1}, false}, {"upperarm_r", {0, 0, 1}, false}, {"lowerarm_l", {1, 0, 0}, false},
                          {"lowerarm_r", {1, 0, 0}, false}, {"head", {0.5, 0.5, 0}, false},   {"thigh_l", {0, 0, 0.5}, true},
                          {"thigh_r", {0, 0, 0.5}, true}};
    for (const Part& part : parts) {
        const int64_t j = m.find_joint(part.joint);
        if (j < 0 || !limits[std::size_t(j)].limited) continue;
        Vector3d angles(rad * part.amount.x() * u(rng), rad * part.amount.y() * u(rng), rad * part.amount.z() * u(rng));
        if (part.one_sided) angles.z() = std::abs(angles.z());
        const Quaterniond P = anatomy::rotation_from_angles(limits[std::size_t(j)], angles);
        q[4 * j] = float(P.x()), q[4 * j + 1] = float(P.y()), q[4 * j + 2] = float(P.z()), q[4 * j + 3] = float(P.w());
    }
    return q;
}

std::vector<float> random_pose(const Model& m, std::mt19937& rng, double amount) {
    const auto& sk = m.data().skeleton;
    const uint32_t J = m.joint_count();
    std::vector<float> q(4 * std::size_t(J), 0.f);
    for (uint32_t j = 0; j < J; ++j) q[4 * j + 3] = 1.f;
    // Rest world rotations W (zero pose): the local pose P with W P W^T = R_body.
    std::vector<Matrix3d> W(J);
    for (uint32_t j = 0; j < J; ++j) {
        const float* r = &sk.rest_orientations[4 * j];
        const Matrix3d R = Quaterniond(r[3], r[0], r[1], r[2]).normalized().toRotationMatrix();
        W[j] = sk.parents[j] < 0 ? R : W[uint32_t(sk.parents[j])] * R;
    }
    const auto limits = anatomy::joint_limits(m);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const auto& range : kRanges) {
        const int64_t j = m.find_joint(range.name);
        if (j < 0) continue;
        auto draw = [&](double lo, double hi) { return amount * (lo + (hi - lo) * u(rng)); };
        Vector3d w(draw(range.x_lo, range.x_hi), draw(range.y_lo, range.y_hi), draw(range.z_lo, range.z_hi));
        // The elbow is a hinge across the arm, not about the body's x axis: its ranges are
        // flexion and forearm rotation in the joint's anatomical frame (joint_limits.hpp).
        if (limits[std::size_t(j)].limited && std::string(range.name).rfind("lowerarm", 0) == 0)
            w = W[std::size_t(j)] * limits[std::size_t(j)].to_anatomical.transpose() * w;
        const double angle = w.norm();
        const Matrix3d Rb = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Matrix3d::Identity();
        const Quaterniond P(W[std::size_t(j)].transpose() * Rb * W[std::size_t(j)]);
        q[4 * j] = float(P.x()), q[4 * j + 1] = float(P.y()), q[4 * j + 2] = float(P.z()), q[4 * j + 3] = float(P.w());
    }
    return q;
}

namespace {

// The model's landmarks on a body's posed vertices.
void place_landmarks(const Model& m, TrueBody& b) {
    const auto& d = m.data();
    b.landmarks.clear();
    for (const auto& l : d.landmarks) {
        if (l.vertex != format::kNone) {
            b.landmarks.push_back(b.vertices[l.vertex]);
            continue;
        }
        Vector3d x = Vector3d::Zero();
        for (int i = 0; i < 3; ++i) x += double(l.barycentric[i]) * b.vertices[d.mesh.triangles[3 * std::size_t(l.triangle) + i]];
        b.landmarks.push_back(x);
    }
}

}  // namespace

TrueBody make_body(const Model& m, std::vector<float> shape, std::vector<float> pose, const Vector3d& translation) {
    TrueBody b;
    b.shape = std::move(shape);
    b.pose = std::move(pose);
    b.translation = translation;
    Body body(m, nullptr);
    body.set_shape(b.shape.data(), uint32_t(b.shape.size()));
    const float t[3] = {float(translation.x()), float(translation.y()), float(translation.z())};
    body.set_pose(b.pose.data(), t);
    const uint32_t V = m.vertex_count();
    const float* p = body.posed();
    b.vertices.resize(V);
    for (uint32_t v = 0; v < V; ++v) b.vertices[v] = Vector3d(p[v], p[V + v], p[2 * std::size_t(V) + v]);
    const float* n = body.normals();
    b.normals.resize(V);
    for (uint32_t v = 0; v < V; ++v) b.normals[v] = Vector3d(n[3 * v], n[3 * v + 1], n[3 * v + 2]).normalized();
    place_landmarks(m, b);
    return b;
}

TrueBody pose_rest_vertices(const Model& m, const std::vector<Vector3d>& rest, std::vector<float> pose, const Vector3d& translation) {
    const auto& d = m.data();
    const auto& sk = d.skeleton;
    const uint32_t V = m.vertex_count(), J = m.joint_count();
    SSC_REQUIRE_ARG(rest.size() == V && pose.size() == 4 * std::size_t(J), "pose_rest_vertices: one rest vertex per model vertex, 4 floats per joint");
    // The model's skeleton on these vertices (its regressor), posed as the format describes:
    // G_j = G_parent [R_j P_j | o_j], a vertex moved by sum_i w_i G_j bind_j^-1.
    std::vector<Vector3d> p(J, Vector3d::Zero());
    for (uint32_t j = 0; j < J; ++j)
        for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e) p[j] += double(sk.regressor_weights[e]) * rest[sk.regressor_vertices[e]];
    std::vector<Matrix3d> W(J), G(J);
    std::vector<Vector3d> t(J);
    for (uint32_t j = 0; j < J; ++j) {
        const float* r = &sk.rest_orientations[4 * j];
        const Matrix3d R = Quaterniond(r[3], r[0], r[1], r[2]).normalized().toRotationMatrix();
        const Matrix3d P = Quaterniond(pose[4 * j + 3], pose[4 * j], pose[4 * j + 1], pose[4 * j + 2]).normalized().toRotationMatrix();
        const int32_t parent = sk.parents[j];
        if (parent < 0) {
            W[j] = R, G[j] = R * P, t[j] = p[j] + translation;
        } else {
            const uint32_t q = uint32_t(parent);
            W[j] = W[q] * R;
            G[j] = G[q] * R * P;
            t[j] = G[q] * (W[q].transpose() * (p[j] - p[q])) + t[q];
        }
    }
    TrueBody b;
    b.pose = std::move(pose);
    b.translation = translation;
    b.vertices.resize(V);
    for (uint32_t v = 0; v < V; ++v) {
        Vector3d x = Vector3d::Zero();
        for (int i = 0; i < 4; ++i) {
            const double w = d.skin.weights[4 * std::size_t(v) + std::size_t(i)];
            if (w == 0) continue;
            const uint32_t j = d.skin.joints[4 * std::size_t(v) + std::size_t(i)];
            x += w * (G[j] * (W[j].transpose() * (rest[v] - p[j])) + t[j]);
        }
        b.vertices[v] = x;
    }
    const std::vector<uint32_t> triangles(d.mesh.triangles.begin(), d.mesh.triangles.end());
    b.normals = registration::vertex_normals(b.vertices, triangles);
    place_landmarks(m, b);
    return b;
}

void transform_body(TrueBody& b, const Matrix3d& R, const Vector3d& t) {
    for (auto& v : b.vertices) v = R * v + t;
    for (auto& n : b.normals) n = R * n;
    for (auto& l : b.landmarks) l = R * l + t;
}

std::vector<fitting::LandmarkTarget> simulate_landmarks(const Model& m, const TrueBody& b, double sd, bool skip_hands,
                                                        std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, sd);
    std::vector<fitting::LandmarkTarget> out;
    const auto& d = m.data();
    for (uint32_t l = 0; l < d.landmarks.size(); ++l) {
        const std::string& name = d.landmarks[l].name;
        if (skip_hands && fitting::is_hand_landmark(name)) continue;
        fitting::LandmarkTarget t;
        t.landmark = l;
        t.position = b.landmarks[l] + Vector3d(n(rng), n(rng), n(rng));
        out.push_back(t);
    }
    return out;
}

fitting::PointCloud simulate_cloud(const Model& m, const TrueBody& b, const CloudSpec& spec, std::mt19937& rng) {
    const auto& tri = m.data().mesh.triangles;
    const std::size_t T = tri.size() / 3;
    std::vector<double> area(T);
    for (std::size_t t = 0; t < T; ++t)
        area[t] = 0.5 * (b.vertices[tri[3 * t + 1]] - b.vertices[tri[3 * t]]).cross(b.vertices[tri[3 * t + 2]] - b.vertices[tri[3 * t]]).norm();
    // Holes: round patches around random surface points, grown until they cover the missing fraction.
    std::vector<uint8_t> removed(T, 0);
    double total = 0;
    for (double a : area) total += a;
    std::discrete_distribution<std::size_t> pick(area.begin(), area.end());
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto centroid = [&](std::size_t t) { return (b.vertices[tri[3 * t]] + b.vertices[tri[3 * t + 1]] + b.vertices[tri[3 * t + 2]]) / 3.0; };
    if (spec.missing > 0) {
        const int holes = 20;  // patches of about 1 % each: occlusions, armpits, soles, hair
        double covered = 0;
        for (int h = 0; h < holes && covered < spec.missing * total; ++h) {
            const Vector3d c = centroid(pick(rng));
            // Triangles by distance from the centre; take the nearest until this hole has its share.
            std::vector<std::pair<double, std::size_t>> byd;
            byd.reserve(T);
            for (std::size_t t = 0; t < T; ++t)
                if (!removed[t]) byd.emplace_back((centroid(t) - c).squaredNorm(), t);
            std::sort(byd.begin(), byd.end());
            const double target = spec.missing * total * double(h + 1) / holes;
            for (const auto& [d2, t] : byd) {
                if (covered >= target) break;
                removed[t] = 1;
                covered += area[t];
            }
        }
    }
    std::vector<double> kept(area);
    for (std::size_t t = 0; t < T; ++t)
        if (removed[t]) kept[t] = 0;
    std::discrete_distribution<std::size_t> sample(kept.begin(), kept.end());
    std::normal_distribution<double> noise(0.0, spec.noise);
    fitting::PointCloud c;
    Vector3d lo = b.vertices[0], hi = b.vertices[0];
    for (const auto& v : b.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const Vector3d pad = 0.1 * (hi - lo);
    lo -= pad, hi += pad;
    for (uint32_t i = 0; i < spec.points; ++i) {
        if (u(rng) < spec.outliers) {
            const Vector3d p(lo.x() + u(rng) * (hi.x() - lo.x()), lo.y() + u(rng) * (hi.y() - lo.y()), lo.z() + u(rng) * (hi.z() - lo.z()));
            c.points.push_back(p);
            if (spec.normals) c.normals.push_back(Vector3d(noise(rng) + 1e-3, noise(rng), noise(rng)).normalized());
            continue;
        }
        const std::size_t t = sample(rng);
        double r1 = u(rng), r2 = u(rng);
        if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
        const Vector3d& a = b.vertices[tri[3 * t]];
        const Vector3d p = a + r1 * (b.vertices[tri[3 * t + 1]] - a) + r2 * (b.vertices[tri[3 * t + 2]] - a);
        c.points.push_back(p + Vector3d(noise(rng), noise(rng), noise(rng)));
        if (spec.normals) c.normals.push_back((b.vertices[tri[3 * t + 1]] - a).cross(b.vertices[tri[3 * t + 2]] - a).normalized());
    }
    return c;
}

double mean_vertex_error(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) s += (a[i] - b[i]).norm();
    return a.empty() ? 0 : s / double(a.size());
}

std::vector<Vector3d> fitted_vertices(const Model& m, const fitting::FitState& s) {
    Body body(m, nullptr);
    std::vector<Vector3d> v;
    fitting::posed_surface(body, s, v);
    return v;
}

void add_bumps(TrueBody& b, const Model& m, int count, std::mt19937& rng) {
    std::uniform_int_distribution<std::size_t> vertex(0, b.vertices.size() - 1);
    std::uniform_real_distribution<double> height(0.01, 0.02), width(0.04, 0.10), sign(-1, 1);
    std::vector<Vector3d> moved = b.vertices;
    for (int k = 0; k < count; ++k) {
        const Vector3d c = b.vertices[vertex(rng)];
        const double h = height(rng) * (sign(rng) < 0 ? -1 : 1), w = width(rng);
        for (std::size_t v = 0; v < b.vertices.size(); ++v)
            moved[v] += h * std::exp(-(b.vertices[v] - c).squaredNorm() / (w * w)) * b.normals[v];
    }
    b.vertices = moved;
    const std::vector<uint32_t> triangles(m.data().mesh.triangles.begin(), m.data().mesh.triangles.end());
    b.normals = registration::vertex_normals(b.vertices, triangles);
}

double best_approximation_error(const Model& m, std::vector<Eigen::Vector3d> rest, bool align, std::vector<Eigen::Vector3d>* approximation,
                                bool with_segments) {
    const fitting::LinearModel lin(m, m.component_count());
    const uint32_t V = m.vertex_count();
    SSC_REQUIRE_ARG(rest.size() == V, "best_approximation_error: one vertex per model vertex");
    const float* mean = m.data().shape.mean.data();
    if (align) {
        Eigen::Matrix3Xd src(3, V), dst(3, V);
        for (uint32_t v = 0; v < V; ++v) src.col(v) = rest[v], dst.col(v) = Eigen::Vector3d(mean[3 * v], mean[3 * v + 1], mean[3 * v + 2]);
        const Similarity T = align_points(src, dst, false);
        for (auto& x : rest) x = T.R * x + T.t;
    }
    const Eigen::Index S = with_segments ? Eigen::Index(m.segment_coefficient_count()) : 0;
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * Eigen::Index(V), lin.K + 3 + S);
    Eigen::VectorXd y(3 * Eigen::Index(V));
    for (uint32_t v = 0; v < V; ++v)
        for (uint32_t a = 0; a < 3; ++a) {
            const Eigen::Index row = 3 * Eigen::Index(v) + a;
            y[row] = rest[v][a] - double(mean[3 * std::size_t(v) + a]);
            for (uint32_t k = 0; k < lin.K; ++k) B(row, k) = lin.basis[(std::size_t(v) * 3 + a) * lin.K + k] * lin.step[k];
            B(row, lin.K + a) = 1;
        }
    if (S > 0)
        for (const SegmentSpace& seg : m.segments()) {
            const std::size_t n = seg.vertices.size();
            for (uint32_t k = 0; k < seg.components; ++k)
                for (uint32_t a = 0; a < 3; ++a)
                    for (std::size_t i = 0; i < n; ++i)
                        B(3 * Eigen::Index(seg.vertices[i]) + a, lin.K + 3 + seg.first + k) = seg.basis[(std::size_t(k) * 3 + a) * n + i];
        }
    const Eigen::VectorXd residual = B * B.colPivHouseholderQr().solve(y) - y;
    double sum = 0;
    for (uint32_t v = 0; v < V; ++v) sum += residual.segment<3>(3 * Eigen::Index(v)).norm();
    if (approximation) {
        approximation->resize(V);
        for (uint32_t v = 0; v < V; ++v) (*approximation)[v] = rest[v] + residual.segment<3>(3 * Eigen::Index(v));
    }
    return sum / double(V);
}

}  // namespace ssc::simulation
