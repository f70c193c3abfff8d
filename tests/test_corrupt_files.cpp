// Model files are untrusted: every corruption is rejected with the right status, never a crash.
#include "support.hpp"

#include "sscape_format/container.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>

using namespace ssc;

namespace {

ssc_status load_status(const std::vector<unsigned char>& bytes, std::size_t size) {
    ssc_model* m = nullptr;
    const ssc_status s = ssc_model_load_memory(nullptr, bytes.data(), size, &m);
    if (s == SSC_OK) {
        REQUIRE(m != nullptr);
        ssc_model_release(m);
    } else {
        REQUIRE(m == nullptr);  // no partial model
        REQUIRE(std::strlen(ssc_last_error()) > 0);
    }
    return s;
}

ssc_status load_status(const std::vector<unsigned char>& bytes) { return load_status(bytes, bytes.size()); }

// Writes a deliberately broken model (validation off) and loads it.
ssc_status load_broken(const std::function<void(format::ModelData&)>& breakit, std::string* message = nullptr) {
    auto built = test::mini_model();
    breakit(built.data);
    format::WriteOptions o;
    o.validate = false;
    const ssc_status s = load_status(format::write_model(built.data, o));
    if (message) *message = ssc_last_error();
    return s;
}

void put_u64(std::vector<unsigned char>& b, std::size_t at, uint64_t v) {
    for (int i = 0; i < 8; ++i) b[at + i] = static_cast<unsigned char>(v >> (8 * i));
}

}  // namespace

TEST_CASE("truncation at every byte offset is rejected", "[corrupt]") {
    const auto bytes = test::mini_bytes();
    REQUIRE(load_status(bytes) == SSC_OK);
    for (std::size_t n = 0; n < bytes.size(); ++n) REQUIRE(load_status(bytes, n) == SSC_ERROR_MODEL_CORRUPT);
}

TEST_CASE("random byte flips are rejected", "[corrupt]") {
    const auto good = test::mini_bytes();
    std::mt19937 rng(123);
    for (int trial = 0; trial < 1500; ++trial) {
        auto bytes = good;
        const int flips = 1 + trial % 4;
        for (int i = 0; i < flips; ++i) bytes[rng() % bytes.size()] ^= static_cast<unsigned char>(1 + rng() % 255);
        // A flip of the major version is reported as such; anything else as corruption.
        const ssc_status s = load_status(bytes);
        REQUIRE((s == SSC_ERROR_MODEL_CORRUPT || s == SSC_ERROR_UNSUPPORTED_VERSION));
    }
}

TEST_CASE("damage inside a well-formed frame is caught by verification", "[corrupt]") {
    // Recompress a damaged FlatBuffer so the checksum passes: the verifier and the semantic
    // validation must catch what remains. A flip may land on a harmless byte (a float that stays
    // finite), so OK is allowed, but most must be rejected, and none may crash.
    const auto good = test::mini_bytes();
    format::ContentBuffer fb;
    format::unpack_container(good.data(), good.size(), format::kDefaultMaxModelBytes, fb);
    std::mt19937 rng(5);
    int rejected = 0;
    const int trials = 400;
    for (int trial = 0; trial < trials; ++trial) {
        std::vector<unsigned char> damaged(fb.begin(), fb.end());
        // Damage the table structure region and random places.
        for (int i = 0; i < 3; ++i) damaged[rng() % damaged.size()] ^= static_cast<unsigned char>(1 + rng() % 255);
        const auto file = format::pack_container(damaged.data(), damaged.size(), 1);
        const ssc_status s = load_status(file);
        REQUIRE((s == SSC_OK || s == SSC_ERROR_MODEL_CORRUPT));
        if (s != SSC_OK) ++rejected;
    }
    CHECK(rejected > trials / 4);
}

TEST_CASE("header problems get the right status", "[corrupt]") {
    const auto good = test::mini_bytes();
    SECTION("wrong magic") {
        auto b = good;
        b[1] = 'X';
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
        CHECK(std::string(ssc_last_error()).find("magic") != std::string::npos);
    }
    SECTION("another major version") {
        auto b = good;
        b[8] = 3;
        CHECK(load_status(b) == SSC_ERROR_UNSUPPORTED_VERSION);
        CHECK(std::string(ssc_last_error()).find("1.x to 2.x") != std::string::npos);
        b[8] = 0;
        CHECK(load_status(b) == SSC_ERROR_UNSUPPORTED_VERSION);
    }
    SECTION("unknown flags") {
        auto b = good;
        b[12] |= 2;
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
    }
    SECTION("absurd content size is refused before allocating") {
        auto b = good;
        put_u64(b, 24, uint64_t(1) << 60);
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
        CHECK(std::string(ssc_last_error()).find("content size") != std::string::npos);
    }
    SECTION("content size above the context's cap") {
        ssc_context_def def;
        ssc_context_def_init(&def, sizeof def);
        def.max_model_bytes = 1000;
        ssc_context* ctx = nullptr;
        REQUIRE(ssc_context_create(&def, &ctx) == SSC_OK);
        ssc_model* m = nullptr;
        CHECK(ssc_model_load_memory(ctx, good.data(), good.size(), &m) == SSC_ERROR_MODEL_CORRUPT);
        CHECK(m == nullptr);
        ssc_context_destroy(ctx);
    }
    SECTION("a damaged checksum") {
        auto b = good;
        b[36] ^= 1;
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
        CHECK(std::string(ssc_last_error()).find("checksum") != std::string::npos);
    }
    SECTION("payload size that disagrees with the file") {
        auto b = good;
        put_u64(b, 16, good.size());
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
    }
    SECTION("trailing bytes") {
        auto b = good;
        b.push_back(0);
        CHECK(load_status(b) == SSC_ERROR_MODEL_CORRUPT);
    }
    SECTION("a frame that does not hold a sscape FlatBuffer") {
        const char text[] = "definitely not a flatbuffer, but long enough to have an identifier";
        CHECK(load_status(format::pack_container(text, sizeof text, 3)) == SSC_ERROR_MODEL_CORRUPT);
    }
}

TEST_CASE("semantic errors are rejected with a message that names them", "[corrupt]") {
    std::string msg;
    CHECK(load_broken([](auto& m) { m.mesh.triangles[5] = m.mesh.vertex_count; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("mesh.triangles") != std::string::npos);
    CHECK(load_broken([](auto& m) { m.mesh.quads[0] = 99999; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.mesh.triangle_uvs[0] = 1u << 30; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.shape.mean[7] = std::numeric_limits<float>::quiet_NaN(); }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("shape.mean") != std::string::npos);
    CHECK(load_broken([](auto& m) { m.shape.stddev[1] = -1.f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.shape.basis.step[0] = std::numeric_limits<float>::infinity(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skeleton.parents[2] = 4; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("parents") != std::string::npos);
    CHECK(load_broken([](auto& m) { m.skeleton.joint_names[3] = m.skeleton.joint_names[1]; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skeleton.regressor_vertices[0] = 100000; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skeleton.regressor_weights[0] += 0.5f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skeleton.rest_orientations[3] = 2.f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skin.joints[8] = 6; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("skin.joints") != std::string::npos);
    CHECK(load_broken([](auto& m) { m.skin.weights[0] = std::numeric_limits<float>::quiet_NaN(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.skin.weights[4] += 0.3f; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("sum") != std::string::npos);
    CHECK(load_broken([](auto& m) { m.landmarks[0].vertex = 1u << 20; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.landmarks.back().triangle = 1u << 20; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.landmarks.back().barycentric[0] = std::numeric_limits<float>::quiet_NaN(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { std::swap(m.vertex_sets[0].vertices[0], m.vertex_sets[0].vertices[1]); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.metadata.units = "cm"; }) == SSC_ERROR_MODEL_CORRUPT);
    // Joint limits: a joint out of range, repeated, a frame that is no rotation, bounds out of order.
    auto limit = [](uint32_t joint) {
        format::JointLimit l;
        l.joint = joint;
        l.lower[0] = -1, l.upper[0] = 1;
        return l;
    };
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(1), limit(2)}; }) == SSC_OK);
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(99)}; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("joint limit") != std::string::npos);
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(2), limit(2)}; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(2)}; m.joint_limits[0].frame[0] = 2; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(2)}; m.joint_limits[0].upper[0] = -2; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { m.joint_limits = {limit(2)}; m.joint_limits[0].lower[1] = std::nanf(""); }) == SSC_ERROR_MODEL_CORRUPT);
    // Joint roles (root, pelvis, spine, head, arm_l, arm_r): one per joint, values in range, a
    // limb with both its joints, the middle one below the upper one.
    auto roles = [](format::ModelData& m) { m.joint_roles.assign(m.joint_count(), format::JointRole{}); };
    auto limb = [](format::ModelData& m, uint32_t upper, uint32_t middle) {
        m.joint_roles[upper] = {2, 1, 0.6, true, 1};
        m.joint_roles[middle] = {2, 1, 0.6, true, 2};
    };
    CHECK(load_broken([&](auto& m) { roles(m); }) == SSC_OK);
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 2, 4); }) == SSC_OK);
    CHECK(load_broken([&](auto& m) { roles(m); m.joint_roles.pop_back(); }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("joint_roles") != std::string::npos);
    CHECK(load_broken([&](auto& m) { roles(m); m.joint_roles[2].part = 6; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { roles(m); m.joint_roles[2].side = 3; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { roles(m); m.joint_roles[2].limb_joint = 3; }) == SSC_ERROR_MODEL_CORRUPT);
    for (double sigma : {0.0, -1.0, 7.0, double(NAN), double(INFINITY)})
        CHECK(load_broken([&](auto& m) { roles(m); m.joint_roles[2].rotation_sigma = sigma; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 2, 4); m.joint_roles[4].limb_joint = 0; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 4, 2); }, &msg) == SSC_ERROR_MODEL_CORRUPT);  // the middle above
    CHECK(msg.find("below") != std::string::npos);
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 4, 5); }) == SSC_ERROR_MODEL_CORRUPT);  // siblings
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 2, 4); m.joint_roles[3] = m.joint_roles[4]; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 2, 4); m.joint_roles[2].part = 0; }) == SSC_ERROR_MODEL_CORRUPT);  // torso
    CHECK(load_broken([&](auto& m) { roles(m); limb(m, 2, 4); m.joint_roles[2].side = m.joint_roles[4].side = 0; }) ==
          SSC_ERROR_MODEL_CORRUPT);
    // Attributes: wrong sizes, an asymmetric or singular covariance, repeated names.
    auto attributes = [](format::ModelData& m) {
        m.attributes.attributes = {{"stature", "m", "", 1.7f, 1.5f, 1.9f, true}, {"mass", "kg", "", 70, 50, 100, true}};
        m.attributes.covariance = {0.01f, 0.1f, 0.1f, 100.f};
        for (uint32_t i = 0; i < 2 * m.component_count(); ++i) m.attributes.shape_covariance.push_back(0.01f * float(i % 3 + i / 3 + 1));
    };
    CHECK(load_broken([&](auto& m) { attributes(m); }) == SSC_OK);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.covariance.pop_back(); }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("attributes") != std::string::npos);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.shape_covariance.push_back(0); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.covariance[1] = 0.2f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.covariance = {0.01f, 1.f, 1.f, 100.f}; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.attributes[1].name = "stature"; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) { attributes(m); m.attributes.attributes[0].minimum = 3; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([&](auto& m) {  // two sliders moving the shape the same way
        attributes(m);
        for (uint32_t k = 0; k < m.component_count(); ++k) m.attributes.shape_covariance[m.component_count() + k] = m.attributes.shape_covariance[k];
    }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("slider") != std::string::npos);
}

TEST_CASE("absurd sizes inside the buffer are refused without huge allocations", "[corrupt]") {
    // A vertex count of 2^31 with small arrays: the size checks fail before anything is sized by it.
    CHECK(load_broken([](auto& m) { m.mesh.vertex_count = 1u << 31; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_broken([](auto& m) { m.mesh.vertex_count = 0xFFFFFFFFu; }) == SSC_ERROR_MODEL_CORRUPT);
    // Claimed components without basis data.
    CHECK(load_broken([](auto& m) {
        m.shape.stddev.resize(100000, 1.f);
        m.shape.basis.step.resize(100000, 1.f);
    }) == SSC_ERROR_MODEL_CORRUPT);
}
