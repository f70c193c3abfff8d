// Named poses: what they look like (arm and leg joint positions), that they respect the joint
// limits, and the C API's handling of bad input.
#include "support.hpp"

#include "anatomy/joint_limits.hpp"
#include "anatomy/named_poses.hpp"
#include "capi/handles.hpp"
#include "fitting/interpenetration.hpp"
#include "registration/registration_quality.hpp"
#include "simulation/simulate.hpp"
#include "simulation/pose_library.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

using namespace ssc;
using Eigen::Vector3d;

namespace {

struct Posed : test::DefaultBody {
    // World position of a joint in the named pose.
    Vector3d joint(const char* pose, const char* name) {
        const uint32_t J = ssc_model_joint_count(model);
        std::vector<float> q(4ull * J), world(16ull * J);
        REQUIRE(ssc_model_get_named_pose(model, pose, q.data(), J) == SSC_OK);
        REQUIRE(ssc_body_set_pose(body, q.data(), J, nullptr) == SSC_OK);
        REQUIRE(ssc_body_get_joint_transforms(body, world.data(), J) == SSC_OK);
        uint32_t j = 0;
        REQUIRE(ssc_model_find_joint(model, name, &j) == SSC_OK);
        return Vector3d(world[16 * j + 12], world[16 * j + 13], world[16 * j + 14]);
    }
};

}  // namespace

TEST_CASE("named poses put the limbs where their names say", "[poses]") {
    Posed p;
    for (const char* side : {"_l", "_r"}) {
        const std::string upper = std::string("upperarm") + side, hand = std::string("hand") + side;
        const std::string thigh = std::string("thigh") + side, calf = std::string("calf") + side, foot = std::string("foot") + side;
        INFO(side);
        // A-pose (rest): the wrists well below the shoulders.
        CHECK(p.joint("a_pose", hand.c_str()).y() < p.joint("a_pose", upper.c_str()).y() - 0.25);
        // T-pose: the wrist level with the shoulder, an arm's length out.
        const Vector3d ts = p.joint("t_pose", upper.c_str()), tw = p.joint("t_pose", hand.c_str());
        CHECK(std::abs(tw.y() - ts.y()) < 0.06);
        CHECK(std::abs(tw.x() - ts.x()) > 0.45);
        // Arms raised: the wrist far above the shoulder.
        CHECK(p.joint("arms_raised", hand.c_str()).y() > p.joint("arms_raised", upper.c_str()).y() + 0.4);
        // Sitting: the knee level with the hip and in front of it, the ankle below the knee.
        const Vector3d hip = p.joint("sitting", thigh.c_str()), knee = p.joint("sitting", calf.c_str()), ankle = p.joint("sitting", foot.c_str());
        CHECK(std::abs(knee.y() - hip.y()) < 0.08);
        CHECK(knee.z() > hip.z() + 0.3);
        CHECK(ankle.y() < knee.y() - 0.3);
        CHECK(std::abs(ankle.z() - knee.z()) < 0.08);
    }
}

TEST_CASE("named poses stay within the anatomical joint limits", "[poses]") {
    Posed p;
    const Model& m = p.model->model;
    const auto limits = anatomy::joint_limits(m);
    for (const auto& pose : anatomy::named_poses()) {
        const auto q = anatomy::named_pose(m, pose.name);
        for (uint32_t j = 0; j < m.joint_count(); ++j) {
            if (!limits[j].limited) continue;
            const Eigen::Quaterniond r(q[4 * j + 3], q[4 * j], q[4 * j + 1], q[4 * j + 2]);
            const Vector3d c = anatomy::anatomical_angles(limits[j], r);
            INFO(pose.name << " " << m.data().skeleton.joint_names[j] << " " << c.transpose());
            for (int a = 0; a < 3; ++a) {
                CHECK(c[a] >= limits[j].lo[a] - 1e-6);
                CHECK(c[a] <= limits[j].hi[a] + 1e-6);
            }
        }
    }
}

TEST_CASE("the benchmark's pose library spans the range of motion within the joint limits", "[poses]") {
    Posed p;
    const Model& m = p.model->model;
    const auto limits = anatomy::joint_limits(m);
    const auto& library = simulation::pose_library();
    CHECK(library.size() >= 40);
    std::vector<std::string> names;
    for (const auto& pose : library) {
        CHECK(std::find(names.begin(), names.end(), pose.name) == names.end());
        names.push_back(pose.name);
        for (const auto& a : pose.angles) CHECK((m.find_joint(a.joint) >= 0 || m.find_joint(std::string(a.joint) + "_l") >= 0));  // no typo
        const auto q = simulation::library_pose(m, pose);
        for (uint32_t j = 0; j < m.joint_count(); ++j) {
            if (!limits[j].limited) continue;
            const Eigen::Quaterniond r(q[4 * j + 3], q[4 * j], q[4 * j + 1], q[4 * j + 2]);
            const Vector3d c = anatomy::anatomical_angles(limits[j], r);
            INFO(pose.name << " " << m.data().skeleton.joint_names[j] << " " << c.transpose() * 180 / M_PI);
            for (int a = 0; a < 3; ++a) {
                CHECK(c[a] >= limits[j].lo[a] - 1e-6);
                CHECK(c[a] <= limits[j].hi[a] + 1e-6);
            }
        }
    }
    // Where the names say: lying puts the head level with the hips.
    for (const char* lying : {"lying_on_back", "lying_on_side", "lying_on_front"}) {
        const auto it = std::find_if(library.begin(), library.end(), [&](const simulation::LibraryPose& l) { return l.name == lying; });
        REQUIRE(it != library.end());
        const uint32_t J = m.joint_count();
        std::vector<float> world(16ull * J);
        const auto q = simulation::library_pose(m, *it);
        REQUIRE(ssc_body_set_pose(p.body, q.data(), J, nullptr) == SSC_OK);
        REQUIRE(ssc_body_get_joint_transforms(p.body, world.data(), J) == SSC_OK);
        const uint32_t head = uint32_t(m.find_joint("head")), pelvis = uint32_t(m.find_joint("pelvis"));
        const Vector3d up = simulation::library_orientation(*it) *
                            Vector3d(world[16 * head + 12] - world[16 * pelvis + 12], world[16 * head + 13] - world[16 * pelvis + 13],
                                     world[16 * head + 14] - world[16 * pelvis + 14]);
        INFO(lying << ": head above the pelvis by " << up.y() << " m");
        CHECK(std::abs(up.y()) < 0.15);
    }
}

// The benchmark's ground truth must be poses people can take: no forearm or lower leg through the
// trunk, the head or another limb (interpenetration.hpp), on the mean body and on bodies far from
// it (heavy bodies leave less room for arms held in front).
TEST_CASE("the benchmark's pose library passes through no body", "[poses]") {
    Posed p;
    const Model& m = p.model->model;
    const fitting::LinearModel lin(m, m.component_count());
    const fitting::InterpenetrationTest inside(lin);
    const std::vector<uint32_t> triangles(m.data().mesh.triangles.begin(), m.data().mesh.triangles.end());
    std::vector<std::vector<float>> shapes{std::vector<float>(m.component_count(), 0.f)};
    std::mt19937 rng(7);
    for (int i = 0; i < 6; ++i) shapes.push_back(simulation::random_shape(m, rng));
    for (const auto& pose : simulation::pose_library())
        for (std::size_t b = 0; b < shapes.size(); ++b) {
            const simulation::TrueBody body = simulation::make_body(m, shapes[b], simulation::library_pose(m, pose), Vector3d::Zero());
            const fitting::LimbsInside in = inside.measure(body.vertices, registration::vertex_normals(body.vertices, triangles));
            INFO(pose.name << " on body " << b << ": " << in.worst << " of the "
                           << (in.limb < 0 ? "" : fitting::region_name(fitting::BodyRegion(in.limb))) << " inside the "
                           << (in.part < 0 ? "" : fitting::region_name(fitting::BodyRegion(in.part))));
            CHECK(in.worst < simulation::kLibraryInside);
        }
}

TEST_CASE("the named pose API rejects bad input without writing", "[poses][capi]") {
    Posed p;
    const uint32_t J = ssc_model_joint_count(p.model);
    REQUIRE(ssc_named_pose_count() == anatomy::named_poses().size());
    const char* name = nullptr;
    const char* description = nullptr;
    REQUIRE(ssc_named_pose_get_info(1, &name, &description) == SSC_OK);
    CHECK(std::string(name) == "t_pose");
    CHECK(std::strlen(description) > 10);
    CHECK(ssc_named_pose_get_info(ssc_named_pose_count(), &name, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    std::vector<float> q(4ull * J, -3.f);
    CHECK(ssc_model_get_named_pose(p.model, "lotus", q.data(), J) == SSC_ERROR_NOT_FOUND);
    CHECK(std::string(ssc_last_error()).find("lotus") != std::string::npos);
    CHECK(ssc_model_get_named_pose(p.model, "sitting", q.data(), J - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_get_named_pose(p.model, nullptr, q.data(), J) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_named_pose(nullptr, "sitting", q.data(), J) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_named_pose(p.model, "sitting", nullptr, J) == SSC_ERROR_INVALID_ARGUMENT);
    for (float v : q) CHECK(v == -3.f);
    // The A-pose is the rest pose: identity everywhere.
    REQUIRE(ssc_model_get_named_pose(p.model, "a_pose", q.data(), J) == SSC_OK);
    for (uint32_t j = 0; j < J; ++j) CHECK(q[4 * j + 3] == 1.f);
}

TEST_CASE("closing the hands curls each fingertip towards its palm and leaves the rest of the pose", "[poses][hands]") {
    Posed p;
    const uint32_t J = ssc_model_joint_count(p.model);
    std::vector<float> q(4ull * J), sitting(4ull * J);
    REQUIRE(ssc_model_get_named_pose(p.model, "sitting", sitting.data(), J) == SSC_OK);
    auto world = [&](const std::vector<float>& pose, const char* name) {
        std::vector<float> w(16ull * J);
        REQUIRE(ssc_body_set_pose(p.body, pose.data(), J, nullptr) == SSC_OK);
        REQUIRE(ssc_body_get_joint_transforms(p.body, w.data(), J) == SSC_OK);
        uint32_t j = 0;
        REQUIRE(ssc_model_find_joint(p.model, name, &j) == SSC_OK);
        return Vector3d(w[16 * j + 12], w[16 * j + 13], w[16 * j + 14]);
    };
    for (const char* side : {"_l", "_r"}) {
        INFO(side);
        const std::string hand = std::string("hand") + side, middle_01 = std::string("middle_01") + side,
                          middle_03 = std::string("middle_03") + side, thigh = std::string("thigh") + side;
        q = sitting;
        const Vector3d wrist = world(q, hand.c_str()), knuckle = world(q, middle_01.c_str()), open_tip = world(q, middle_03.c_str());
        REQUIRE(ssc_model_close_hands(p.model, 1.0f, 1.0f, q.data(), J) == SSC_OK);
        const Vector3d closed_tip = world(q, middle_03.c_str());
        // The middle finger's end joint comes back towards the wrist: about level with the knuckles.
        CHECK((closed_tip - wrist).norm() < (open_tip - wrist).norm() - 0.02);
        CHECK((closed_tip - wrist).norm() < (knuckle - wrist).norm() + 0.02);
        // Only fingers moved: the sitting pose's thigh and the wrist stay.
        CHECK((world(q, thigh.c_str()) - world(sitting, thigh.c_str())).norm() < 1e-6);
        CHECK((world(q, hand.c_str()) - wrist).norm() < 1e-6);
        // Closure 0 is the open hand.
        REQUIRE(ssc_model_close_hands(p.model, 0.0f, 0.0f, q.data(), J) == SSC_OK);
        CHECK((world(q, middle_03.c_str()) - open_tip).norm() < 1e-6);
    }
    // Bad input: a clear status, the rotations untouched.
    q = sitting;
    CHECK(ssc_model_close_hands(p.model, 1.5f, 0.0f, q.data(), J) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("[0, 1]") != std::string::npos);
    CHECK(ssc_model_close_hands(p.model, 0.0f, std::nanf(""), q.data(), J) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_close_hands(p.model, 0.5f, 0.5f, q.data(), J - 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_close_hands(p.model, 0.5f, 0.5f, nullptr, J) != SSC_OK);
    CHECK(ssc_model_close_hands(nullptr, 0.5f, 0.5f, q.data(), J) != SSC_OK);
    CHECK(q == sitting);
}

TEST_CASE("random shapes are reproducible, within their truncation, and refuse bad arguments", "[synthesis][capi]") {
    Posed p;
    const uint32_t K = ssc_model_shape_count(p.model), n = 200;
    std::vector<float> a(std::size_t(n) * K), b(a.size());
    REQUIRE(ssc_model_sample_shapes(p.model, 7, n, 2.5f, a.data(), uint32_t(a.size())) == SSC_OK);
    REQUIRE(ssc_model_sample_shapes(p.model, 7, n, 2.5f, b.data(), uint32_t(b.size())) == SSC_OK);
    CHECK(a == b);
    REQUIRE(ssc_model_sample_shapes(p.model, 8, n, 2.5f, b.data(), uint32_t(b.size())) == SSC_OK);
    CHECK(a != b);
    double sum = 0, sum2 = 0, largest = 0;
    for (float c : a) sum += c, sum2 += double(c) * c, largest = std::max(largest, double(std::abs(c)));
    CHECK(largest <= 2.5);
    CHECK(std::abs(sum / double(a.size())) < 0.02);                // mean 0
    CHECK(std::sqrt(sum2 / double(a.size())) == Approx(0.95).margin(0.03));  // a normal truncated at 2.5 SD: sd 0.95
    CHECK(ssc_model_sample_shapes(p.model, 7, n, 2.5f, a.data(), uint32_t(a.size()) - 1) != SSC_OK);
    CHECK(ssc_model_sample_shapes(p.model, 7, n, 0.0f, a.data(), uint32_t(a.size())) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_sample_shapes(p.model, 7, n, std::nanf(""), a.data(), uint32_t(a.size())) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_sample_shapes(nullptr, 7, n, 2.5f, a.data(), uint32_t(a.size())) != SSC_OK);
}

TEST_CASE("an axis-angle vector becomes the quaternion the body poses with", "[synthesis][capi]") {
    Posed p;
    const float aa[3] = {0.0f, 0.0f, float(M_PI / 2)};
    float q[4] = {0, 0, 0, 0};
    REQUIRE(ssc_rotation_from_axis_angle(aa, q) == SSC_OK);
    CHECK(q[0] == Approx(0.0f).margin(1e-7));
    CHECK(q[2] == Approx(std::sin(M_PI / 4)));
    CHECK(q[3] == Approx(std::cos(M_PI / 4)));
    const float zero[3] = {0, 0, 0};
    REQUIRE(ssc_rotation_from_axis_angle(zero, q) == SSC_OK);
    CHECK(q[3] == 1.0f);
    const float bad[3] = {std::nanf(""), 0, 0};
    CHECK(ssc_rotation_from_axis_angle(bad, q) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_rotation_from_axis_angle(nullptr, q) != SSC_OK);
    CHECK(ssc_rotation_from_axis_angle(aa, nullptr) != SSC_OK);
}
