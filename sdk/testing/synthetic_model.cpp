#include "synthetic_model.hpp"

#include "anatomy/joint_limits.hpp"
#include "common/error.hpp"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <random>
#include <string>

namespace ssc::testing {
namespace {

using Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;

struct Bone {
    std::string name;
    int parent;
    Vector3d head, tail;  // the joint and the end of its segment
    double radius;
    std::string part;     // vertex set
};

std::vector<Bone> humanoid() {
    std::vector<Bone> b;
    auto add = [&](const std::string& name, int parent, Vector3d head, Vector3d tail, double r, const char* part) {
        b.push_back({name, parent, head, tail, r, part});
        return static_cast<int>(b.size()) - 1;
    };
    const int root = add("root", -1, {0, 0.02, 0}, {0, 0.06, 0}, 0.02, "torso");
    const int pelvis = add("pelvis", root, {0, 0.95, 0}, {0, 1.05, 0}, 0.16, "torso");
    const int s1 = add("spine_01", pelvis, {0, 1.05, 0}, {0, 1.2, 0}, 0.14, "torso");
    const int s2 = add("spine_02", s1, {0, 1.2, 0}, {0, 1.33, 0}, 0.15, "torso");
    const int s3 = add("spine_03", s2, {0, 1.33, 0}, {0, 1.48, 0}, 0.16, "torso");
    const int neck = add("neck_01", s3, {0, 1.48, 0}, {0, 1.58, 0}, 0.055, "head");
    add("head", neck, {0, 1.58, 0.01}, {0, 1.78, 0.01}, 0.095, "head");
    for (int side = 0; side < 2; ++side) {
        const double sx = side == 0 ? 1 : -1;
        const std::string sfx = side == 0 ? "_l" : "_r";
        const int cl = add("clavicle" + sfx, s3, {sx * 0.03, 1.44, 0.02}, {sx * 0.17, 1.44, 0}, 0.045, "arms");
        const Vector3d down(sx * std::cos(0.8), -std::sin(0.8), 0);  // A-pose arms
        const Vector3d sh(sx * 0.19, 1.43, 0), el = sh + 0.29 * down, wr = el + 0.26 * down, kn = wr + 0.09 * down;
        const int ua = add("upperarm" + sfx, cl, sh, el, 0.05, "arms");
        const int la = add("lowerarm" + sfx, ua, el, wr, 0.04, "arms");
        const int hand = add("hand" + sfx, la, wr, kn, 0.03, "hands");
        const char* fingers[5] = {"thumb", "index", "middle", "ring", "pinky"};
        for (int f = 0; f < 5; ++f) {
            // Fingers fan out around the hand's direction; the thumb points forward.
            const double spread = (f - 2) * 0.012;
            Vector3d base = kn + Vector3d(0, 0, spread);
            Vector3d dir = f == 0 ? Vector3d(sx * 0.3, -0.5, 0.8).normalized() : down;
            if (f == 0) base = wr + 0.03 * down + Vector3d(0, 0, 0.03);
            const double len = f == 0 ? 0.025 : 0.028 - 0.002 * std::abs(f - 2);
            int parent = hand;
            for (int seg = 1; seg <= 3; ++seg) {
                const Vector3d a = base + (seg - 1) * len * dir, c = base + seg * len * dir;
                parent = add(std::string(fingers[f]) + "_0" + std::to_string(seg) + sfx, parent, a, c, 0.008, "hands");
            }
        }
    }
    for (int side = 0; side < 2; ++side) {
        const double sx = side == 0 ? 1 : -1;
        const std::string sfx = side == 0 ? "_l" : "_r";
        const int th = add("thigh" + sfx, pelvis, {sx * 0.1, 0.92, 0}, {sx * 0.1, 0.5, 0}, 0.075, "legs");
        const int ca = add("calf" + sfx, th, {sx * 0.1, 0.5, 0}, {sx * 0.1, 0.09, 0}, 0.05, "legs");
        const int ft = add("foot" + sfx, ca, {sx * 0.1, 0.09, 0}, {sx * 0.1, 0.04, 0.13}, 0.04, "feet");
        add("ball" + sfx, ft, {sx * 0.1, 0.04, 0.13}, {sx * 0.1, 0.03, 0.2}, 0.03, "feet");
    }
    return b;
}

std::vector<Bone> mini() {
    return {
        {"root", -1, {0, 0, 0}, {0, 0.3, 0}, 0.05, "torso"},
        {"pelvis", 0, {0, 0.3, 0}, {0, 0.6, 0}, 0.12, "torso"},
        {"spine", 1, {0, 0.6, 0}, {0, 1.0, 0}, 0.1, "torso"},
        {"head", 2, {0, 1.0, 0}, {0, 1.2, 0}, 0.08, "head"},
        {"arm_l", 2, {0.12, 0.9, 0}, {0.6, 0.9, 0}, 0.04, "arms"},
        {"arm_r", 2, {-0.12, 0.9, 0}, {-0.6, 0.9, 0}, 0.04, "arms"},
    };
}

// Rotation taking +Y to d.
Eigen::Quaterniond align_y(const Vector3d& d) { return Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitY(), d); }

}  // namespace

SyntheticModel build_synthetic_model(const SyntheticSpec& spec) {
    const std::vector<Bone> bones = spec.skeleton == SyntheticSkeleton::Humanoid53 ? humanoid() : mini();
    const std::size_t B = bones.size();
    // Vertex budget: tubes of `sides` x `rings` plus two poles, rings by surface area. The
    // largest segment takes the remainder with its own side count so the total is exact.
    const uint32_t sides = spec.skeleton == SyntheticSkeleton::Humanoid53 ? 12 : 8;
    std::vector<double> area(B);
    double total_area = 0;
    for (std::size_t i = 0; i < B; ++i) total_area += area[i] = bones[i].radius * ((bones[i].tail - bones[i].head).norm() + 2 * bones[i].radius);
    std::size_t big = 0;
    for (std::size_t i = 1; i < B; ++i) if (area[i] > area[big]) big = i;
    std::vector<uint32_t> rings(B), seg_sides(B, sides);
    const double budget = double(spec.vertex_count) - 2.0 * B;
    SSC_REQUIRE_ARG(budget > 4.0 * B * sides, "vertex_count too small for this skeleton");
    for (std::size_t i = 0; i < B; ++i) rings[i] = std::max<uint32_t>(2, uint32_t(budget * area[i] / total_area / sides));
    auto used = [&] { uint64_t n = 0; for (std::size_t i = 0; i < B; ++i) if (i != big) n += uint64_t(rings[i]) * seg_sides[i] + 2; return n; };
    bool found = false;
    for (int attempt = 0; attempt < 64 && !found; ++attempt) {
        const int64_t rest = int64_t(spec.vertex_count) - int64_t(used()) - 2;
        for (uint32_t s = sides; s <= 4 * sides && !found; ++s)
            if (rest > 0 && rest % s == 0 && rest / s >= 2) { seg_sides[big] = s; rings[big] = uint32_t(rest / s); found = true; }
        if (!found) rings[(big + 1 + attempt) % B == big ? (big + 2) % B : (big + 1 + attempt) % B] += 1;
    }
    SSC_REQUIRE_ARG(found, "cannot split vertex_count over the segments");

    SyntheticModel out;
    format::ModelData& m = out.data;
    m.metadata.name = spec.skeleton == SyntheticSkeleton::Humanoid53 ? "synthetic-capsule-humanoid" : "synthetic-mini";
    m.metadata.model_version = "1";
    m.metadata.license = "CC0-1.0";
    m.metadata.provenance = "procedural: sscape build_synthetic_model, seed " + std::to_string(spec.seed);
    m.metadata.description = "Procedural test model: capsule segments around a skeleton, random smooth shape components.";

    // World rest rotations: +Y along each bone (or identity).
    std::vector<Eigen::Quaterniond> world(B);
    for (std::size_t i = 0; i < B; ++i)
        world[i] = spec.aligned_rest_orientations ? align_y((bones[i].tail - bones[i].head).normalized()) : Eigen::Quaterniond::Identity();

    std::vector<Vector3d> pos;
    std::vector<std::array<std::pair<uint32_t, double>, 3>> infl;
    std::vector<float> uv;
    std::vector<uint32_t> first_ring_start(B), ring_sides(B), pole_top(B);
    std::vector<std::vector<uint32_t>> part_vertices;
    std::vector<std::string> part_names;
    auto part_index = [&](const std::string& p) {
        for (std::size_t i = 0; i < part_names.size(); ++i) if (part_names[i] == p) return i;
        part_names.push_back(p);
        part_vertices.emplace_back();
        return part_names.size() - 1;
    };
    for (std::size_t i = 0; i < B; ++i) {
        const Bone& b = bones[i];
        const Vector3d axis = b.tail - b.head;
        const Vector3d d = axis.normalized();
        const Vector3d u = (std::abs(d.z()) < 0.9 ? d.cross(Vector3d::UnitZ()) : d.cross(Vector3d::UnitX())).normalized();
        const Vector3d w = d.cross(u);
        const uint32_t S = seg_sides[i], R = rings[i];
        int child = -1;
        for (std::size_t c = i + 1; c < B && child < 0; ++c) if (bones[c].parent == int(i)) child = int(c);
        const std::size_t part = part_index(b.part);
        auto add_vertex = [&](const Vector3d& p, double t, float uu) {
            // Blend with the parent near the joint and with the first child near the end.
            const double wp = b.parent >= 0 && t < 0.2 ? 0.5 * (1 - t / 0.2) : 0.0;
            const double wc = child >= 0 && t > 0.8 ? 0.5 * (t - 0.8) / 0.2 : 0.0;
            infl.push_back({std::make_pair(uint32_t(i), 1 - wp - wc), std::make_pair(uint32_t(b.parent < 0 ? 0 : b.parent), wp),
                            std::make_pair(uint32_t(child < 0 ? 0 : child), wc)});
            part_vertices[part].push_back(uint32_t(pos.size()));
            pos.push_back(p);
            uv.push_back(uu);
            uv.push_back(float(t));
        };
        first_ring_start[i] = uint32_t(pos.size());
        ring_sides[i] = S;
        for (uint32_t r = 0; r < R; ++r) {
            const double t = double(r) / (R - 1);
            // Tubes taper slightly and bulge in the middle, like limbs.
            const double rad = b.radius * (1.0 + 0.15 * std::sin(kPi * t) - 0.1 * t);
            for (uint32_t s = 0; s < S; ++s) {
                const double a = 2 * kPi * s / S;
                add_vertex(b.head + t * axis + rad * (std::cos(a) * u + std::sin(a) * w), t, float(s) / S);
            }
        }
        add_vertex(b.head - 0.6 * b.radius * d, 0.0, 0.5f);  // bottom pole
        pole_top[i] = uint32_t(pos.size());
        add_vertex(b.tail + 0.6 * b.radius * d, 1.0, 0.5f);  // top pole
        // Quads between rings, fans at the poles; counter-clockwise seen from outside
        // ((u, w, d) is right-handed, so angle then axis order faces outwards).
        const uint32_t base = first_ring_start[i], bottom = pole_top[i] - 1, top = pole_top[i];
        for (uint32_t r = 0; r + 1 < R; ++r)
            for (uint32_t s = 0; s < S; ++s) {
                const uint32_t a = base + r * S + s, b2 = base + r * S + (s + 1) % S;
                const uint32_t c = b2 + S, e = a + S;
                for (uint32_t idx : {a, b2, c, e}) m.mesh.quads.push_back(idx);
            }
        for (uint32_t s = 0; s < S; ++s) {
            const uint32_t a = base + s, b2 = base + (s + 1) % S;
            for (uint32_t idx : {bottom, b2, a}) m.mesh.triangles.push_back(idx);
            const uint32_t ta = base + (R - 1) * S + s, tb = base + (R - 1) * S + (s + 1) % S;
            for (uint32_t idx : {top, ta, tb}) m.mesh.triangles.push_back(idx);
        }
    }
    const uint32_t V = uint32_t(pos.size());
    if (V != spec.vertex_count) fail(SSC_ERROR_INTERNAL, "synthetic vertex count mismatch");
    m.mesh.vertex_count = V;
    for (std::size_t q = 0; q < m.mesh.quads.size(); q += 4) {
        const uint32_t* c = &m.mesh.quads[q];
        for (uint32_t idx : {c[0], c[1], c[2], c[0], c[2], c[3]}) m.mesh.triangles.push_back(idx);
    }
    m.mesh.uvs.assign(uv.begin(), uv.end());
    m.mesh.triangle_uvs = m.mesh.triangles;
    m.mesh.quad_uvs = m.mesh.quads;

    // Skeleton: joints at the bone heads; each joint regressed from its first ring (whose centroid
    // is the head exactly, the ring being uniform).
    auto& sk = m.skeleton;
    sk.regressor_offsets.push_back(0);
    for (std::size_t i = 0; i < B; ++i) {
        sk.joint_names.push_back(bones[i].name);
        sk.parents.push_back(bones[i].parent);
        const Eigen::Quaterniond local = bones[i].parent < 0 ? world[i] : world[bones[i].parent].conjugate() * world[i];
        for (double c : {local.x(), local.y(), local.z(), local.w()}) sk.rest_orientations.push_back(float(c));
        for (uint32_t s = 0; s < ring_sides[i]; ++s) {
            sk.regressor_vertices.push_back(first_ring_start[i] + s);
            sk.regressor_weights.push_back(1.0f / ring_sides[i]);
        }
        sk.regressor_offsets.push_back(uint32_t(sk.regressor_vertices.size()));
    }
    // The anatomical table limits the joints it names (the humanoid's), as training does.
    m.joint_limits = anatomy::compute_joint_limits(sk);
    for (uint32_t v = 0; v < V; ++v) {
        // Merge duplicate joints, keep the 4 largest (at most 3 here), normalise.
        float wsum = 0;
        uint16_t js[4] = {0, 0, 0, 0};
        float ws[4] = {0, 0, 0, 0};
        int n = 0;
        for (const auto& [j, w] : infl[v]) {
            if (w <= 0) continue;
            int slot = -1;
            for (int k = 0; k < n; ++k) if (js[k] == j) slot = k;
            if (slot < 0) { slot = n++; js[slot] = uint16_t(j); }
            ws[slot] += float(w);
            wsum += float(w);
        }
        for (int k = 0; k < 4; ++k) {
            m.skin.joints.push_back(js[k]);
            m.skin.weights.push_back(ws[k] / wsum);
        }
    }

    // Shape space: smooth random fields (sums of sinusoids of the rest position, wavelengths
    // shrinking with the component index), orthonormalised, with decaying standard deviations.
    std::mt19937 rng(spec.seed);
    std::normal_distribution<double> normal;
    const uint32_t K = spec.components;
    const std::size_t rows = 3ull * V;
    Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(rows, K);
    for (uint32_t k = 0; k < K; ++k) {
        const double wavelength = 1.6 / std::sqrt(1.0 + k);
        for (int term = 0; term < 3; ++term) {
            Vector3d freq(normal(rng), normal(rng), normal(rng));
            freq *= 2 * kPi / wavelength / freq.norm();
            const Vector3d amp(normal(rng), normal(rng), normal(rng));
            const double phase = 2 * kPi * std::uniform_real_distribution<double>()(rng);
            for (uint32_t v = 0; v < V; ++v) {
                const double s = std::sin(freq.dot(pos[v]) + phase);
                for (int a = 0; a < 3; ++a) basis(a * V + v, k) += amp[a] * s;
            }
        }
    }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(basis);
    basis = qr.householderQ() * Eigen::MatrixXd::Identity(rows, K);
    m.shape.stddev.resize(K);
    out.basis_float.resize(rows * K);
    for (uint32_t k = 0; k < K; ++k) {
        // Per-vertex RMS displacement of 3 cm for the first component, decaying like 1/k.
        const double sd = 0.03 * std::sqrt(double(V)) / (1.0 + k);
        m.shape.stddev[k] = float(sd);
        for (std::size_t r = 0; r < rows; ++r) out.basis_float[k * rows + r] = float(sd * basis(r, k));
    }
    m.shape.basis = format::quantize_basis(out.basis_float.data(), V, K, spec.tolerance, &out.quantization);
    m.shape.mean.resize(rows);
    for (uint32_t v = 0; v < V; ++v)
        for (int a = 0; a < 3; ++a) m.shape.mean[3 * v + a] = float(pos[v][a]);

    // Landmarks: a vertex one and a barycentric one per bone end that users would name.
    auto add_vertex_landmark = [&](const std::string& name, uint32_t v) {
        format::Landmark l;
        l.name = name;
        l.vertex = v;
        m.landmarks.push_back(l);
    };
    for (std::size_t i = 0; i < B; ++i)
        if (bones[i].name == "head" || bones[i].name == "ball_l" || bones[i].name == "ball_r" ||
            bones[i].name == "arm_l" || bones[i].name == "middle_03_l" || bones[i].name == "middle_03_r")
            add_vertex_landmark(bones[i].name + "_tip", pole_top[i]);
    format::Landmark navel;
    navel.name = "front_center";
    navel.triangle = 0;
    navel.barycentric[0] = navel.barycentric[1] = navel.barycentric[2] = 1.0f / 3;
    m.landmarks.push_back(navel);
    for (std::size_t p = 0; p < part_names.size(); ++p) {
        format::VertexSet set;
        set.name = part_names[p];
        set.vertices.assign(part_vertices[p].begin(), part_vertices[p].end());
        m.vertex_sets.push_back(std::move(set));
    }
    format::validate_model(m);
    return out;
}

}  // namespace ssc::testing
