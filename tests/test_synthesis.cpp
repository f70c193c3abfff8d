// Synthesis against hand-computed expectations.
#include "support.hpp"

#include "capi/handles.hpp"
#include "common/files.hpp"
#include "common/thread_pool.hpp"
#include "synthesis/body.hpp"
#include "synthesis/kernels_skin_xyz.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>

using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

struct Fixture {
    ssc::testing::SyntheticModel built;
    test::ModelPtr model;
    test::BodyPtr body;
    uint32_t V, J, K;

    explicit Fixture(bool aligned = false) : built(test::mini_model(aligned)) {
        model = test::load(ssc::format::write_model(built.data));
        REQUIRE(model);
        body = test::body(model.get());
        REQUIRE(body);
        V = ssc_model_vertex_count(model.get());
        J = ssc_model_joint_count(model.get());
        K = ssc_model_shape_count(model.get());
    }
    std::vector<float> transforms() {
        std::vector<float> t(16ull * J);
        REQUIRE(ssc_body_get_joint_transforms(body.get(), t.data(), J) == SSC_OK);
        return t;
    }
};

Vector3d at(const std::vector<float>& v, uint32_t i) { return Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]); }

}  // namespace

TEST_CASE("the zero pose returns the rest shape", "[synthesis]") {
    Fixture f;
    const float shape[4] = {1.5f, -2.0f, 0.5f, 3.0f};
    REQUIRE(ssc_body_set_shape(f.body.get(), shape, 4) == SSC_OK);
    const auto rest = test::rest(f.model.get(), f.body.get());
    const auto posed = test::posed(f.model.get(), f.body.get());
    REQUIRE(rest.size() == posed.size());
    for (std::size_t i = 0; i < rest.size(); ++i) REQUIRE(posed[i] == Approx(rest[i]).margin(1e-6));
}

TEST_CASE("a shape coefficient c moves vertices by c x stddev x basis vector", "[synthesis]") {
    Fixture f;
    const auto mean = test::rest(f.model.get(), f.body.get());
    const auto& d = f.built.data;
    const std::size_t rows = 3ull * f.V;
    for (uint32_t k = 0; k < f.K; ++k) {
        std::vector<float> c(f.K, 0.f);
        c[k] = 2.5f;
        REQUIRE(ssc_body_set_shape(f.body.get(), c.data(), f.K) == SSC_OK);
        const auto moved = test::rest(f.model.get(), f.body.get());
        for (uint32_t v = 0; v < f.V; ++v)
            for (int a = 0; a < 3; ++a) {
                // stddev x unit basis vector = the stored scaled basis, step x q.
                const std::size_t i = k * rows + a * f.V + v;
                const double expected = 2.5 * d.shape.basis.step[k] * d.shape.basis.q[i];
                REQUIRE(moved[3 * v + a] - mean[3 * v + a] == Approx(expected).margin(2e-6));
                // and the unquantized basis within the quantization tolerance
                REQUIRE(std::abs(moved[3 * v + a] - mean[3 * v + a] - 2.5 * f.built.basis_float[i]) < 1e-4);
            }
    }
    // Fewer coefficients than components: the rest are zero.
    const float one[1] = {1.0f};
    REQUIRE(ssc_body_set_shape(f.body.get(), one, 1) == SSC_OK);
    std::vector<float> back(f.K);
    REQUIRE(ssc_body_get_shape(f.body.get(), back.data(), f.K) == SSC_OK);
    CHECK(back[0] == 1.0f);
    for (uint32_t k = 1; k < f.K; ++k) CHECK(back[k] == 0.0f);
}

static void check_rotation(bool aligned) {
    Fixture f(aligned);
    uint32_t head = 0;
    REQUIRE(ssc_model_find_joint(f.model.get(), "head", &head) == SSC_OK);
    const auto rest_t = f.transforms();
    const auto rest = test::rest(f.model.get(), f.body.get());
    // 90 degrees about the joint's local X axis.
    std::vector<float> q(4ull * f.J, 0.f);
    for (uint32_t j = 0; j < f.J; ++j) q[4 * j + 3] = 1.f;
    q[4 * head + 0] = float(std::sin(M_PI / 4));
    q[4 * head + 3] = float(std::cos(M_PI / 4));
    REQUIRE(ssc_body_set_pose(f.body.get(), q.data(), f.J, nullptr) == SSC_OK);
    const auto posed = test::posed(f.model.get(), f.body.get());

    // Expected: the head's rest frame W (rotation) and position p from its rest world transform;
    // the rotation in world space is W Rx(90) W^T about p. Vertices blend by their skin weights.
    Matrix3d W;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) W(r, c) = rest_t[16 * head + 4 * c + r];
    const Vector3d p(rest_t[16 * head + 12], rest_t[16 * head + 13], rest_t[16 * head + 14]);
    if (!aligned) CHECK(W.isIdentity(1e-6));
    const Matrix3d R = W * Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix() * W.transpose();
    std::vector<uint16_t> joints(4ull * f.V);
    std::vector<float> weights(4ull * f.V);
    REQUIRE(ssc_model_get_skin(f.model.get(), joints.data(), weights.data(), f.V) == SSC_OK);
    int moved = 0;
    for (uint32_t v = 0; v < f.V; ++v) {
        const Vector3d x = at(rest, v);
        Vector3d expected = Vector3d::Zero();
        for (int i = 0; i < 4; ++i) {
            const double w = weights[4 * v + i];
            expected += w * (joints[4 * v + i] == head ? Vector3d(R * (x - p) + p) : x);
        }
        REQUIRE((at(posed, v) - expected).norm() < 2e-6);
        if ((expected - x).norm() > 1e-3) ++moved;
    }
    CHECK(moved > 10);  // the head's vertices really moved
    // The head's world transform is the rotated frame at the same place.
    const auto posed_t = f.transforms();
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) CHECK(posed_t[16 * head + 4 * c + r] == Approx((R * W)(r, c)).margin(1e-6));
}

TEST_CASE("rotating one joint by 90 degrees moves its skinned vertices as the math says", "[synthesis]") {
    SECTION("identity rest orientations") { check_rotation(false); }
    SECTION("bone-aligned rest orientations") { check_rotation(true); }
}

TEST_CASE("axis-angle and quaternion poses agree, and translation moves everything", "[synthesis]") {
    Fixture f(true);
    std::vector<float> aa(3ull * f.J, 0.f), q(4ull * f.J, 0.f);
    for (uint32_t j = 0; j < f.J; ++j) {
        const Vector3d axis = Vector3d(0.3 * j + 0.1, -0.2, 0.5).normalized();
        const double angle = 0.2 + 0.1 * j;
        const Eigen::Quaterniond qq(Eigen::AngleAxisd(angle, axis));
        for (int a = 0; a < 3; ++a) aa[3 * j + a] = float(axis[a] * angle);
        q[4 * j] = float(qq.x()); q[4 * j + 1] = float(qq.y()); q[4 * j + 2] = float(qq.z()); q[4 * j + 3] = float(qq.w());
    }
    const float t[3] = {0.5f, -1.0f, 2.0f};
    REQUIRE(ssc_body_set_pose(f.body.get(), q.data(), f.J, nullptr) == SSC_OK);
    const auto a = test::posed(f.model.get(), f.body.get());
    REQUIRE(ssc_body_set_pose_axis_angle(f.body.get(), aa.data(), f.J, nullptr) == SSC_OK);
    const auto b = test::posed(f.model.get(), f.body.get());
    REQUIRE(ssc_body_set_pose_axis_angle(f.body.get(), aa.data(), f.J, t) == SSC_OK);
    const auto c = test::posed(f.model.get(), f.body.get());
    for (std::size_t i = 0; i < a.size(); ++i) {
        REQUIRE(a[i] == Approx(b[i]).margin(1e-5));
        REQUIRE(c[i] - b[i] == Approx(t[i % 3]).margin(1e-5));
    }
}

TEST_CASE("skinning matrices, world transforms and inverse binds are consistent", "[synthesis]") {
    Fixture f(true);
    const float shape[2] = {1.0f, -1.0f};
    REQUIRE(ssc_body_set_shape(f.body.get(), shape, 2) == SSC_OK);
    std::vector<float> aa(3ull * f.J, 0.f);
    for (uint32_t j = 0; j < f.J; ++j) aa[3 * j + (j % 3)] = 0.4f;
    const float t[3] = {0.1f, 0.2f, 0.3f};
    REQUIRE(ssc_body_set_pose_axis_angle(f.body.get(), aa.data(), f.J, t) == SSC_OK);
    std::vector<float> world(16ull * f.J), inv(16ull * f.J), skin(16ull * f.J);
    REQUIRE(ssc_body_get_joint_transforms(f.body.get(), world.data(), f.J) == SSC_OK);
    REQUIRE(ssc_body_get_inverse_bind_matrices(f.body.get(), inv.data(), f.J) == SSC_OK);
    REQUIRE(ssc_body_get_skinning_matrices(f.body.get(), skin.data(), f.J) == SSC_OK);
    for (uint32_t j = 0; j < f.J; ++j) {
        const Eigen::Map<const Eigen::Matrix4f> Wm(&world[16 * j]), Im(&inv[16 * j]), Sm(&skin[16 * j]);
        REQUIRE((Wm * Im - Sm).cwiseAbs().maxCoeff() < 1e-5f);
        REQUIRE(Sm(3, 3) == 1.0f);
    }
    const auto rest = test::rest(f.model.get(), f.body.get());
    const auto posed = test::posed(f.model.get(), f.body.get());
    std::vector<uint16_t> joints(4ull * f.V);
    std::vector<float> weights(4ull * f.V);
    REQUIRE(ssc_model_get_skin(f.model.get(), joints.data(), weights.data(), f.V) == SSC_OK);
    for (uint32_t v = 0; v < f.V; ++v) {
        Eigen::Vector4f x(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2], 1.f), p = Eigen::Vector4f::Zero();
        for (int i = 0; i < 4; ++i) p += weights[4 * v + i] * Eigen::Map<const Eigen::Matrix4f>(&skin[16 * joints[4 * v + i]]) * x;
        for (int a = 0; a < 3; ++a) REQUIRE(posed[3 * v + a] == Approx(p[a]).margin(1e-5));
    }
}

TEST_CASE("normals are unit length and point out of the surface", "[synthesis]") {
    Fixture f;
    std::vector<float> n(3ull * f.V);
    REQUIRE(ssc_body_get_normals(f.body.get(), n.data(), f.V, 0) == SSC_OK);
    for (uint32_t v = 0; v < f.V; ++v) REQUIRE(at(n, v).norm() == Approx(1.0).margin(1e-5));
    uint32_t tip = 0;
    REQUIRE(ssc_model_find_landmark(f.model.get(), "head_tip", &tip) == SSC_OK);
    const auto& lm = f.built.data.landmarks[tip];
    CHECK(n[3 * lm.vertex + 1] > 0.99f);  // the top of the head faces up
}

TEST_CASE("strided output equals packed output, and landmarks follow the body", "[synthesis]") {
    Fixture f;
    const auto packed = test::posed(f.model.get(), f.body.get());
    std::vector<float> wide(5ull * f.V, -7.f);
    REQUIRE(ssc_body_get_vertices(f.body.get(), wide.data(), f.V, 20) == SSC_OK);
    for (uint32_t v = 0; v < f.V; ++v) {
        for (int a = 0; a < 3; ++a) REQUIRE(wide[5 * v + a] == packed[3 * v + a]);
        REQUIRE(wide[5 * v + 3] == -7.f);  // gaps untouched
    }
    const uint32_t L = ssc_model_landmark_count(f.model.get());
    REQUIRE(L > 0);
    std::vector<float> lm_model(3ull * L), lm_body(3ull * L);
    REQUIRE(ssc_model_get_landmark_positions(f.model.get(), lm_model.data(), L, 0) == SSC_OK);
    REQUIRE(ssc_body_get_landmarks(f.body.get(), lm_body.data(), L, 0) == SSC_OK);
    for (std::size_t i = 0; i < lm_model.size(); ++i) REQUIRE(lm_body[i] == Approx(lm_model[i]).margin(1e-6));
}

TEST_CASE("a batch gives what single bodies give", "[synthesis][batch]") {
    Fixture f(true);
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    def.worker_count = 2;
    ssc_context* ctx = nullptr;
    REQUIRE(ssc_context_create(&def, &ctx) == SSC_OK);
    auto model = test::load(ssc::format::write_model(f.built.data), ctx);
    ssc_context_destroy(ctx);  // the model keeps its context alive
    REQUIRE(model);
    const uint32_t n = 19;  // not a multiple of the group size
    std::vector<float> shapes(n * 3ull), poses(n * 3ull * f.J), trans(3ull * n);
    for (std::size_t i = 0; i < shapes.size(); ++i) shapes[i] = float(std::sin(i * 1.7));
    for (std::size_t i = 0; i < poses.size(); ++i) poses[i] = float(0.3 * std::cos(i * 0.9));
    for (std::size_t i = 0; i < trans.size(); ++i) trans[i] = float(i) * 0.01f;
    std::vector<float> verts(n * 3ull * f.V), normals(n * 3ull * f.V);
    ssc_batch_desc desc;
    ssc_batch_desc_init(&desc, sizeof desc);
    desc.body_count = n;
    desc.shapes = shapes.data();
    desc.shape_count = 3;
    desc.pose_format = SSC_ROTATION_AXIS_ANGLE;
    desc.poses = poses.data();
    desc.translations = trans.data();
    desc.vertices = verts.data();
    desc.vertices_capacity = n * f.V;
    desc.normals = normals.data();
    desc.normals_capacity = n * f.V;
    REQUIRE(ssc_model_synthesize_batch(model.get(), &desc) == SSC_OK);
    auto b = test::body(model.get());
    for (uint32_t i = 0; i < n; ++i) {
        REQUIRE(ssc_body_set_shape(b.get(), &shapes[3 * i], 3) == SSC_OK);
        REQUIRE(ssc_body_set_pose_axis_angle(b.get(), &poses[3ull * f.J * i], f.J, &trans[3 * i]) == SSC_OK);
        const auto one = test::posed(model.get(), b.get());
        std::vector<float> nn(3ull * f.V);
        REQUIRE(ssc_body_get_normals(b.get(), nn.data(), f.V, 0) == SSC_OK);
        for (std::size_t k = 0; k < one.size(); ++k) {
            REQUIRE(verts[i * 3ull * f.V + k] == one[k]);
            REQUIRE(normals[i * 3ull * f.V + k] == nn[k]);
        }
    }
}

TEST_CASE("a body split over a pool's threads gives what one thread gives", "[synthesis][threads]") {
    ssc_model* handle = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &handle) == SSC_OK);
    const ssc::Model& m = handle->model;
    ssc::ThreadPool pool(3);
    ssc::Body one(m, nullptr), split(m, nullptr);
    split.set_pool(&pool);
    std::vector<float> shape(m.component_count()), quats(4ull * m.joint_count());
    for (std::size_t k = 0; k < shape.size(); ++k) shape[k] = float(1.5 * std::sin(0.7 * double(k) + 0.3));
    for (uint32_t j = 0; j < m.joint_count(); ++j) {
        const Eigen::Quaternionf q(Eigen::AngleAxisf(0.4f * std::cos(1.3f * float(j)), Eigen::Vector3f(1, std::sin(float(j)), 0.5f).normalized()));
        quats[4 * j] = q.x(), quats[4 * j + 1] = q.y(), quats[4 * j + 2] = q.z(), quats[4 * j + 3] = q.w();
    }
    const float translation[3] = {0.1f, -0.2f, 0.3f};
    for (ssc::Body* b : {&one, &split}) {
        b->set_shape(shape.data(), uint32_t(shape.size()));
        b->set_pose(quats.data(), translation);
    }
    const std::size_t n = 3ull * m.vertex_count();
    const float *p1 = one.posed(), *p2 = split.posed(), *n1 = one.normals(), *n2 = split.normals();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < n; ++i) differ += p1[i] != p2[i] || n1[i] != n2[i];
    CHECK(differ == 0);
    // The pose moved the body: the comparison is not between two rest meshes.
    CHECK(std::abs(p1[0] - one.rest_planar()[0]) > 1e-3f);
    ssc_model_release(handle);
}

TEST_CASE("synthesis keeps the bits it had: vertices, normals, landmarks, matrices, a level and a batch", "[synthesis][isa]") {
    // A digest of what the default model synthesizes for fixed shapes and poses, recorded when the
    // kernels were last changed on purpose. Speed work must keep it (issue 51: every CPU path gives
    // the same bits as before): a change here means results that users have stored would move.
    // It holds for this platform's libm (sines and cosines of axis-angle poses).
    ssc_model* m = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &m) == SSC_OK);
    ssc_body* b = nullptr;
    REQUIRE(ssc_body_create(m, nullptr, &b) == SSC_OK);
    const uint32_t V = ssc_model_vertex_count(m), J = ssc_model_joint_count(m), K = ssc_model_shape_count(m), L = ssc_model_landmark_count(m);
    std::vector<float> bytes, out(3ull * V), shape(K), pose(3ull * J), mats(48ull * J);
    auto keep = [&](const float* p, std::size_t n) { bytes.insert(bytes.end(), p, p + n); };
    for (int s = 0; s < 2; ++s) {
        for (uint32_t i = 0; i < K; ++i) shape[i] = 1.5f * std::sin(float(i) * 1.3f + float(s));
        REQUIRE(ssc_body_set_shape(b, shape.data(), K) == SSC_OK);
        for (int p = 0; p < 3; ++p) {  // the first posing of a shape in vertex order, the others in slot order
            for (uint32_t j = 0; j < 3 * J; ++j) pose[j] = 0.4f * std::sin(float(j) * 0.7f + float(p) * 2.1f + float(s));
            REQUIRE(ssc_body_set_pose_axis_angle(b, pose.data(), J, nullptr) == SSC_OK);
            REQUIRE(ssc_body_get_vertices(b, out.data(), V, 0) == SSC_OK);
            keep(out.data(), 3ull * V);
            REQUIRE(ssc_body_get_normals(b, out.data(), V, 0) == SSC_OK);
            keep(out.data(), 3ull * V);
            REQUIRE(ssc_body_get_landmarks(b, out.data(), L, 0) == SSC_OK);
            keep(out.data(), 3ull * L);
            REQUIRE(ssc_body_get_joint_transforms(b, mats.data(), J) == SSC_OK);
            REQUIRE(ssc_body_get_inverse_bind_matrices(b, mats.data() + 16ull * J, J) == SSC_OK);
            REQUIRE(ssc_body_get_skinning_matrices(b, mats.data() + 32ull * J, J) == SSC_OK);
            keep(mats.data(), mats.size());
            ssc_level_info info{};
            info.struct_size = sizeof info;
            REQUIRE(ssc_model_get_level_info(m, ssc_model_level_count(m) - 1, &info) == SSC_OK);
            REQUIRE(ssc_body_get_level_vertices(b, ssc_model_level_count(m) - 1, out.data(), info.vertex_count, 0) == SSC_OK);
            keep(out.data(), 3ull * info.vertex_count);
        }
    }
    const uint32_t n = 9;
    std::vector<float> shapes(std::size_t(n) * K), poses(std::size_t(n) * 3 * J), verts(std::size_t(n) * 3 * V);
    for (std::size_t i = 0; i < shapes.size(); ++i) shapes[i] = std::sin(float(i) * 0.37f);
    for (std::size_t i = 0; i < poses.size(); ++i) poses[i] = 0.3f * std::sin(float(i) * 0.11f);
    ssc_batch_desc d;
    ssc_batch_desc_init(&d, sizeof d);
    d.body_count = n, d.shapes = shapes.data(), d.shape_count = K, d.pose_format = SSC_ROTATION_AXIS_ANGLE, d.poses = poses.data();
    d.vertices = verts.data(), d.vertices_capacity = std::size_t(n) * V;
    REQUIRE(ssc_model_synthesize_batch(m, &d) == SSC_OK);
    keep(verts.data(), verts.size());
    INFO("active kernels: " << ssc::kernels::isa_name(ssc::kernels::active_isa()));
    CHECK(ssc::content_digest(bytes.data(), 4 * bytes.size()) == "ca2ea78e13549c3e");
    ssc_body_destroy(b);
    ssc_model_release(m);
}

TEST_CASE("a body posed again skins in slot order with the same bits, on every instruction set and thread count", "[synthesis][isa]") {
    // The first posing of a shape skins in vertex order; later ones keep the rest in the skin
    // layout's slot order (Body::posed_slots) and convert on the way out. Both must give exactly
    // what skin_slots gives, through posed() and through the xyz output, whichever is asked first.
    // (With AVX-512 every posing skins by blocks, writing the planar positions beside the xyz only
    // once posed() has been used: the xyz-first body's first posing makes them when asked.)
    ssc_model* handle = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &handle) == SSC_OK);
    const ssc::Model& m = handle->model;
    namespace k = ssc::kernels;
    const uint32_t K = m.component_count(), J = m.joint_count(), V = m.vertex_count();
    const ssc::SkinLayout& layout = m.skin_layout();
    for (uint32_t v = 0; v < V; ++v) REQUIRE(layout.vertices[layout.first_slot[v]] == v);
    auto quats_for = [&](float phase) {
        std::vector<float> q4(4ull * J);
        for (uint32_t j = 0; j < J; ++j) {
            const Eigen::Quaternionf q(Eigen::AngleAxisf(0.6f * std::sin(phase + 1.3f * float(j)), Eigen::Vector3f(0.2f, 1, std::cos(float(j))).normalized()));
            q4[4 * j] = q.x(), q4[4 * j + 1] = q.y(), q4[4 * j + 2] = q.z(), q4[4 * j + 3] = q.w();
        }
        return q4;
    };
    std::vector<float> shape(K);
    for (uint32_t i = 0; i < K; ++i) shape[i] = float(1.5 * std::cos(0.7 * double(i)));
    ssc::ThreadPool pool(3);
    for (const bool threaded : {false, true})
        for (const bool xyz_first : {false, true}) {
            ssc::Body body(m, nullptr);
            if (threaded) body.set_pool(&pool);
            body.set_shape(shape.data(), K);
            for (int posing = 0; posing < 4; ++posing) {
                const std::vector<float> q = quats_for(0.9f * float(posing));
                const float t[3] = {0.1f * float(posing), -0.2f, 0.05f};
                body.set_pose(q.data(), t);
                std::vector<float> expected(3ull * V, -1.f);
                k::skin_slots(m, body.rest_planar(), body.skinning(), expected.data(), 0, k::skin_slot_count(m), k::Isa::Baseline);
                std::vector<float> xyz(3ull * V, -1.f), planar;
                if (xyz_first) body.posed_xyz(xyz.data(), 12);
                planar.assign(body.posed(), body.posed() + 3ull * V);
                if (!xyz_first) body.posed_xyz(xyz.data(), 12);
                INFO("posing " << posing << (threaded ? ", 3 threads" : ", 1 thread") << (xyz_first ? ", xyz first" : ", planar first"));
                CHECK(planar == expected);
                bool same = true;
                for (uint32_t v = 0; v < V; ++v)
                    for (int c = 0; c < 3; ++c) same = same && xyz[3 * v + c] == expected[c * std::size_t(V) + v];
                CHECK(same);
                // Strided output (16 bytes a vertex) through the scalar path.
                std::vector<float> strided(4ull * V, -7.f);
                body.set_pose(q.data(), t);
                body.posed_xyz(strided.data(), 16);
                bool strided_same = true;
                for (uint32_t v = 0; v < V; ++v)
                    for (int c = 0; c < 3; ++c) strided_same = strided_same && strided[4 * v + c] == expected[c * std::size_t(V) + v];
                CHECK(strided_same);
            }
        }
    // The slot-order kernels themselves on every instruction set.
    ssc::Body body(m, nullptr);
    body.set_shape(shape.data(), K);
    const std::vector<float> q = quats_for(0.4f);
    body.set_pose(q.data(), nullptr);
    const uint32_t S = layout.slot_count();
    std::vector<float> rest_slots(3ull * S), expected(3ull * V);
    k::to_slot_order(layout, body.rest_planar(), rest_slots.data(), 0, S);
    {  // (on this run's instruction set: its loads, gathers or permutes copy each slot's vertex)
        bool copied = true;
        for (uint32_t s = 0; s < S; ++s)
            for (int c = 0; c < 3; ++c) copied = copied && rest_slots[c * std::size_t(S) + s] == body.rest_planar()[c * std::size_t(V) + layout.vertices[s]];
        CHECK(copied);
    }
    k::skin_slots(m, body.rest_planar(), body.skinning(), expected.data(), 0, k::skin_slot_count(m), k::Isa::Baseline);
    for (int isa = 0; isa < 3; ++isa) {
        INFO("isa " << k::isa_name(k::Isa(isa)));
        std::vector<float> slots(3ull * S, -1.f), planar(3ull * V, -1.f);
        k::skin_slots_in_slot_order(layout, rest_slots.data(), body.skinning(), slots.data(), 0, S, k::Isa(isa));
        k::from_slot_order(layout, slots.data(), planar.data(), 0, V);
        CHECK(planar == expected);
        // Skinning that writes the caller's xyz as it goes (every vertex written, each exactly once
        // in value, none outside the buffer: the guard floats after it stay).
        std::vector<float> both(3ull * S, -1.f), xyz(3ull * V + 16, -3.f);
        k::skin_slots_and_xyz(layout, rest_slots.data(), body.skinning(), both.data(), xyz.data(), 0, S, k::Isa(isa));
        CHECK(both == slots);
        bool same = true;
        for (uint32_t v = 0; v < V; ++v)
            for (int c = 0; c < 3; ++c) same = same && xyz[3 * v + c] == expected[c * std::size_t(V) + v];
        CHECK(same);
        CHECK(std::all_of(xyz.begin() + 3 * std::ptrdiff_t(V), xyz.end(), [](float x) { return x == -3.f; }));
    }
    ssc_model_release(handle);
}

TEST_CASE("every instruction set's shape and skinning kernels give the baseline's bits", "[synthesis][isa]") {
    // The library is built for plain x86-64 and picks AVX2 or AVX-512 kernels at run time; the
    // plain kernels are what an older CPU runs. Paths the CPU lacks fall back (and are reported).
    ssc_model* handle = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &handle) == SSC_OK);
    const ssc::Model& m = handle->model;
    namespace k = ssc::kernels;
    INFO("this CPU supports " << k::isa_name(k::supported_isa()) << "; active: " << k::isa_name(k::active_isa()));
    const uint32_t K = m.component_count(), J = m.joint_count(), V = m.vertex_count();
    // Batches of 1, 3 and 9 bodies take every tile shape of the kernels.
    for (std::size_t count : {std::size_t(1), std::size_t(3), std::size_t(9)}) {
        std::vector<std::vector<float>> scaled(count, std::vector<float>(K));
        for (std::size_t g = 0; g < count; ++g) {
            std::vector<float> c(K);
            for (uint32_t i = 0; i < K; ++i) c[i] = float(2.0 * std::sin(0.37 * double(i) + double(g)));
            k::scale_coefficients(m, c.data(), scaled[g].data());
        }
        std::vector<const float*> in(count);
        for (std::size_t g = 0; g < count; ++g) in[g] = scaled[g].data();
        std::vector<std::vector<float>> rest[3];
        for (int isa = 0; isa < 3; ++isa) {
            rest[isa].assign(count, std::vector<float>(m.padded_rows(), -1.f));
            std::vector<float*> out(count);
            for (std::size_t g = 0; g < count; ++g) out[g] = rest[isa][g].data();
            k::shape_rows(m, count, in.data(), out.data(), 0, m.padded_rows() / ssc::Model::kChunk, k::Isa(isa));
        }
        CHECK(rest[1] == rest[0]);
        CHECK(rest[2] == rest[0]);
    }
    // Skinning of a posed body.
    ssc::Body body(m, nullptr);
    std::vector<float> shape(K, 0.5f), quats(4ull * J);
    for (uint32_t j = 0; j < J; ++j) {
        const Eigen::Quaternionf q(Eigen::AngleAxisf(0.5f * std::sin(1.7f * float(j)), Eigen::Vector3f(1, std::cos(float(j)), 0.3f).normalized()));
        quats[4 * j] = q.x(), quats[4 * j + 1] = q.y(), quats[4 * j + 2] = q.z(), quats[4 * j + 3] = q.w();
    }
    body.set_shape(shape.data(), K);
    body.set_pose(quats.data(), nullptr);
    std::vector<float> posed[3];
    for (int isa = 0; isa < 3; ++isa) {
        posed[isa].assign(3ull * V, -1.f);
        k::skin_slots(m, body.rest_planar(), body.skinning(), posed[isa].data(), 0, k::skin_slot_count(m), k::Isa(isa));
    }
    CHECK(posed[1] == posed[0]);
    CHECK(posed[2] == posed[0]);
    CHECK(std::vector<float>(body.posed(), body.posed() + 3ull * V) == posed[0]);  // what the body itself gives
    // The levels of detail's layouts (short runs: the AVX-512 path's half-width last steps).
    for (uint32_t l = 0; l < m.level_count(); ++l) {
        const ssc::SkinLayout& layout = m.level_skin(l);
        const float* rest = body.level_rest(l);
        std::vector<float> level_posed[3];
        for (int isa = 0; isa < 3; ++isa) {
            level_posed[isa].assign(3ull * layout.vertex_count, -1.f);
            k::skin_slots(layout, rest, body.skinning(), level_posed[isa].data(), 0, layout.slot_count(), k::Isa(isa));
        }
        INFO("level " << l);
        CHECK(level_posed[1] == level_posed[0]);
        CHECK(level_posed[2] == level_posed[0]);
    }
    ssc_model_release(handle);
}

TEST_CASE("skinning by blocks of 16 vertices gives the skin layout's bits, signed zeros included, on every instruction set", "[synthesis][isa]") {
    // skin_blocks (skin_blocks.hpp) blends each lane's joints in SkinLayout's order from -0 and masks
    // off the joints a lane lacks: bit for bit skin_slots, even where an element blends to zero
    // (the zero pose's off-diagonal elements, a vertex on the mirror plane at x = 0).
    namespace k = ssc::kernels;
    auto bits_equal = [](const std::vector<float>& a, const std::vector<float>& b) {
        return a.size() == b.size() && std::memcmp(a.data(), b.data(), 4 * a.size()) == 0;
    };
    auto check = [&](const ssc::SkinLayout& layout, const ssc::SkinBlocks& blocks, const float* rest, const k::SkinMatrix* mats) {
        const uint32_t V = layout.vertex_count;
        REQUIRE(blocks.vertex_count == V);
        std::vector<float> expected(3ull * V, -1.f);
        k::skin_slots(layout, rest, mats, expected.data(), 0, layout.slot_count(), k::Isa::Baseline);
        for (int isa = 0; isa < 3; ++isa) {
            INFO("isa " << k::isa_name(k::Isa(isa)));
            std::vector<float> planar(3ull * V, -1.f), xyz(3ull * V + 16, -3.f), again(3ull * V, -1.f);
            k::skin_blocks(blocks, rest, mats, planar.data(), xyz.data(), 0, blocks.block_count(), k::Isa(isa));
            CHECK(bits_equal(planar, expected));
            std::vector<float> interleaved(3ull * V);
            for (uint32_t v = 0; v < V; ++v)
                for (int c = 0; c < 3; ++c) interleaved[3 * v + c] = expected[c * std::size_t(V) + v];
            CHECK(bits_equal(std::vector<float>(xyz.begin(), xyz.begin() + 3 * std::ptrdiff_t(V)), interleaved));
            CHECK(std::all_of(xyz.begin() + 3 * std::ptrdiff_t(V), xyz.end(), [](float x) { return x == -3.f; }));  // nothing past the buffer
            // Two block ranges (two threads' shares) write what one does.
            const uint32_t half = blocks.block_count() / 2;
            k::skin_blocks(blocks, rest, mats, again.data(), nullptr, half, blocks.block_count(), k::Isa(isa));
            k::skin_blocks(blocks, rest, mats, again.data(), nullptr, 0, half, k::Isa(isa));
            CHECK(bits_equal(again, expected));
        }
    };
    SECTION("the default model, in the zero pose and posed") {
        ssc_model* handle = nullptr;
        REQUIRE(ssc_model_load_default(nullptr, &handle) == SSC_OK);
        const ssc::Model& m = handle->model;
        const uint32_t K = m.component_count(), J = m.joint_count();
        REQUIRE(m.vertex_count() % ssc::SkinBlocks::kLanes != 0);  // a partial last block
        ssc::Body body(m, nullptr);
        std::vector<float> shape(K, 0.f), quats(4ull * J, 0.f);
        for (uint32_t j = 0; j < J; ++j) quats[4 * j + 3] = 1.f;
        body.set_shape(shape.data(), K);
        body.set_pose(quats.data(), nullptr);
        check(m.skin_layout(), m.skin_blocks(), body.rest_planar(), body.skinning());
        for (uint32_t j = 0; j < J; ++j) {
            const Eigen::Quaternionf q(Eigen::AngleAxisf(0.7f * std::sin(2.1f * float(j)), Eigen::Vector3f(std::cos(float(j)), 1, 0.4f).normalized()));
            quats[4 * j] = q.x(), quats[4 * j + 1] = q.y(), quats[4 * j + 2] = q.z(), quats[4 * j + 3] = q.w();
        }
        for (uint32_t i = 0; i < K; ++i) shape[i] = float(std::sin(1.1 * double(i)));
        body.set_shape(shape.data(), K);
        const float t[3] = {0.3f, -0.1f, 0.2f};
        body.set_pose(quats.data(), t);
        check(m.skin_layout(), m.skin_blocks(), body.rest_planar(), body.skinning());
        ssc_model_release(handle);
    }
    SECTION("vertices naming a joint twice, unused influences and signed zeros in the matrices") {
        constexpr uint32_t V = 37, J = 6;  // two whole blocks and 5 vertices
        std::vector<uint16_t> joints(4 * V);
        std::vector<float> weights(4 * V), rest(3 * V);
        for (uint32_t v = 0; v < V; ++v) {
            for (uint32_t i = 0; i < 4; ++i) {
                joints[4 * v + i] = uint16_t((v * 7 + i * (v % 3 + 1)) % J);
                weights[4 * v + i] = (v + i) % 5 == 0 ? 0.f : (v + i) % 7 == 0 ? -0.5f : 0.1f + 0.2f * float(i);
            }
            if (v % 4 == 0) joints[4 * v + 1] = joints[4 * v];  // the same joint twice
            if (v % 9 == 0) weights[4 * v] = 1.f, weights[4 * v + 1] = weights[4 * v + 2] = weights[4 * v + 3] = 0.f;
            for (int c = 0; c < 3; ++c) rest[c * V + v] = float(std::sin(double(v) + c));
            if (v % 6 == 0) {  // on joint 0 alone, at x = -0: its x blends to a signed zero
                joints[4 * v] = 0, weights[4 * v] = 0.5f, weights[4 * v + 1] = weights[4 * v + 2] = weights[4 * v + 3] = 0.f;
                rest[v] = -0.f, rest[V + v] = 0.5f, rest[2 * V + v] = 0.7f;
            }
        }
        std::vector<k::SkinMatrix> mats(J);
        for (uint32_t j = 0; j < J; ++j)
            for (int e = 0; e < 16; ++e) mats[j].m[e] = (e + j) % 4 == 0 ? ((e + j) % 8 == 0 ? 0.f : -0.f) : float(std::cos(double(e) * 0.7 + j));
        for (int e = 0; e < 16; ++e) mats[0].m[e] = e % 5 == 0 ? 1.f : -0.f;  // the identity, every other element -0
        const ssc::SkinLayout layout = ssc::build_skin_layout(V, joints.data(), weights.data(), nullptr);
        const ssc::SkinBlocks blocks = ssc::build_skin_blocks(V, joints.data(), weights.data(), nullptr);
        check(layout, blocks, rest.data(), mats.data());
    }
}
