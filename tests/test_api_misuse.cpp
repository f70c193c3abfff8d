// API misuse: NULL handles and buffers, short buffers, wrong counts, NaN/Inf parameters.
// Each gives an error status and a message, and writes nothing.
#include "support.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

namespace {

constexpr float kSentinel = -12345.f;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

bool untouched(const std::vector<float>& v) {
    for (float x : v) if (x != kSentinel) return false;
    return true;
}

struct MiniBody {
    test::ModelPtr model = test::load(test::mini_bytes());
    test::BodyPtr body;
    uint32_t V, J, K;
    MiniBody() {
        REQUIRE(model);
        body = test::body(model.get());
        REQUIRE(body);
        V = ssc_model_vertex_count(model.get());
        J = ssc_model_joint_count(model.get());
        K = ssc_model_shape_count(model.get());
    }
};

}  // namespace

TEST_CASE("status names and the last error", "[api]") {
    CHECK(std::string(ssc_status_name(SSC_OK)) == "SSC_OK");
    CHECK(std::string(ssc_status_name(SSC_ERROR_MODEL_CORRUPT)) == "SSC_ERROR_MODEL_CORRUPT");
    CHECK(std::string(ssc_status_name(static_cast<ssc_status>(-999))) == "SSC_UNKNOWN_STATUS");
    for (int s = 0; s >= -9; --s) CHECK(std::string(ssc_status_name(static_cast<ssc_status>(s))) != "SSC_UNKNOWN_STATUS");
    CHECK(ssc_version() == SSC_VERSION_NUMBER);
    CHECK(ssc_body_set_shape(nullptr, nullptr, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("body is NULL") != std::string::npos);
}

TEST_CASE("NULL handles and pointers are errors", "[api]") {
    MiniBody f;
    ssc_model* m = nullptr;
    const auto bytes = test::mini_bytes();
    CHECK(ssc_model_load_memory(nullptr, nullptr, 10, &m) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_load_memory(nullptr, bytes.data(), bytes.size(), nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_load_file(nullptr, nullptr, &m) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_context_create(nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_create(nullptr, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_body* b = nullptr;
    CHECK(ssc_body_create(nullptr, nullptr, &b) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(b == nullptr);
    CHECK(ssc_model_vertex_count(nullptr) == 0);
    CHECK(ssc_model_joint_count(nullptr) == 0);
    uint32_t idx = 77;
    CHECK(ssc_model_find_joint(nullptr, "head", &idx) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_find_joint(f.model.get(), nullptr, &idx) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_find_joint(f.model.get(), "head", nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(idx == 77);
    CHECK(ssc_body_get_vertices(f.body.get(), nullptr, f.V, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_get_vertices(nullptr, nullptr, 0, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_pose(nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_synthesize_batch(f.model.get(), nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    const char* s = nullptr;
    CHECK(ssc_model_get_metadata(f.model.get(), SSC_METADATA_NAME, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_metadata(f.model.get(), static_cast<ssc_metadata_key>(42), &s) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(s == nullptr);
    // Destroy and release accept NULL.
    ssc_body_destroy(nullptr);
    ssc_model_release(nullptr);
    ssc_model_retain(nullptr);
    ssc_context_destroy(nullptr);
}

TEST_CASE("unknown names and indices", "[api]") {
    MiniBody f;
    uint32_t idx = 5;
    CHECK(ssc_model_find_joint(f.model.get(), "no_such_joint", &idx) == SSC_ERROR_NOT_FOUND);
    CHECK(ssc_model_find_landmark(f.model.get(), "no_such_landmark", &idx) == SSC_ERROR_NOT_FOUND);
    CHECK(idx == 5);
    const char* name = nullptr;
    CHECK(ssc_model_get_joint_name(f.model.get(), f.J, &name) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_landmark_name(f.model.get(), 1000, &name) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_vertex_set(f.model.get(), 1000, &name, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(name == nullptr);
    REQUIRE(ssc_model_get_joint_name(f.model.get(), 3, &name) == SSC_OK);
    CHECK(std::string(name) == "head");
}

TEST_CASE("short buffers and bad strides write nothing", "[api]") {
    MiniBody f;
    std::vector<float> out(3ull * f.V + 64, kSentinel);
    CHECK(ssc_body_get_vertices(f.body.get(), out.data(), f.V - 1, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_normals(f.body.get(), out.data(), 0, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_rest_vertices(f.body.get(), out.data(), f.V - 1, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_vertices(f.body.get(), out.data(), f.V, 8) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_get_vertices(f.body.get(), out.data(), f.V, 13) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_get_joint_transforms(f.body.get(), out.data(), f.J - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_skinning_matrices(f.body.get(), out.data(), 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_inverse_bind_matrices(f.body.get(), out.data(), 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_landmarks(f.body.get(), out.data(), 0, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_shape(f.body.get(), out.data(), f.K - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_get_shape_stddevs(f.model.get(), out.data(), f.K - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_get_uvs(f.model.get(), out.data(), 3) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_get_landmark_positions(f.model.get(), out.data(), 0, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(untouched(out));
    std::vector<uint32_t> idx(16, 99);
    CHECK(ssc_model_get_triangles(f.model.get(), idx.data(), 5) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_get_vertex_set_indices(f.model.get(), 0, idx.data(), 2) == SSC_ERROR_BUFFER_TOO_SMALL);
    std::vector<int32_t> parents(16, 99);
    CHECK(ssc_model_get_joint_parents(f.model.get(), parents.data(), f.J - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    for (auto x : idx) CHECK(x == 99u);
    for (auto x : parents) CHECK(x == 99);
}

TEST_CASE("wrong counts and NaN/Inf parameters leave the body unchanged", "[api]") {
    MiniBody f;
    const float good_shape[2] = {0.5f, -0.5f};
    REQUIRE(ssc_body_set_shape(f.body.get(), good_shape, 2) == SSC_OK);
    const auto before = test::posed(f.model.get(), f.body.get());

    std::vector<float> shape(f.K + 1, 0.1f);
    CHECK(ssc_body_set_shape(f.body.get(), shape.data(), f.K + 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_shape(f.body.get(), nullptr, 2) == SSC_ERROR_INVALID_ARGUMENT);
    shape[1] = kNaN;
    CHECK(ssc_body_set_shape(f.body.get(), shape.data(), 2) == SSC_ERROR_INVALID_ARGUMENT);
    shape[1] = kInf;
    CHECK(ssc_body_set_shape(f.body.get(), shape.data(), 2) == SSC_ERROR_INVALID_ARGUMENT);

    std::vector<float> q(4ull * f.J, 0.f);
    for (uint32_t j = 0; j < f.J; ++j) q[4 * j + 3] = 1.f;
    CHECK(ssc_body_set_pose(f.body.get(), q.data(), f.J - 1, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    q[5] = kNaN;
    CHECK(ssc_body_set_pose(f.body.get(), q.data(), f.J, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    q[5] = 0.f;
    q[4] = q[5] = q[6] = q[7] = 0.f;  // zero quaternion
    CHECK(ssc_body_set_pose(f.body.get(), q.data(), f.J, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    q[7] = 1.f;
    const float bad_t[3] = {0.f, kInf, 0.f};
    CHECK(ssc_body_set_pose(f.body.get(), q.data(), f.J, bad_t) == SSC_ERROR_INVALID_ARGUMENT);
    std::vector<float> aa(3ull * f.J, 0.f);
    aa[2] = -kInf;
    CHECK(ssc_body_set_pose_axis_angle(f.body.get(), aa.data(), f.J, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_pose(f.body.get(), nullptr, 3, nullptr) == SSC_ERROR_INVALID_ARGUMENT);

    const auto after = test::posed(f.model.get(), f.body.get());
    REQUIRE(after == before);
}

TEST_CASE("bad def structs are rejected", "[api]") {
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    ssc_context* ctx = nullptr;
    def.struct_size = sizeof def + 4;  // from a newer header than the library knows
    CHECK(ssc_context_create(&def, &ctx) == SSC_ERROR_INVALID_ARGUMENT);
    def.struct_size = 0;
    CHECK(ssc_context_create(&def, &ctx) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_context_def_init(&def, sizeof def);
    def.alloc = [](void*, size_t size, size_t) { return std::malloc(size); };
    CHECK(ssc_context_create(&def, &ctx) == SSC_ERROR_INVALID_ARGUMENT);  // alloc without free
    CHECK(ctx == nullptr);
    // An older caller's smaller struct: the rest are defaults.
    ssc_context_def_init(&def, sizeof def);
    def.struct_size = offsetof(ssc_context_def, alloc);
    def.worker_count = 1;
    REQUIRE(ssc_context_create(&def, &ctx) == SSC_OK);
    ssc_context_destroy(ctx);
}

TEST_CASE("batch misuse writes nothing", "[api][batch]") {
    MiniBody f;
    const uint32_t n = 3;
    std::vector<float> verts(n * 3ull * f.V, kSentinel);
    std::vector<float> shapes(n * f.K, 0.2f);
    ssc_batch_desc d;
    ssc_batch_desc_init(&d, sizeof d);
    d.body_count = n;
    d.shapes = shapes.data();
    d.shape_count = f.K;
    d.vertices = verts.data();
    d.vertices_capacity = n * f.V - 1;
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_BUFFER_TOO_SMALL);
    d.vertices_capacity = n * f.V;
    d.shape_count = f.K + 1;
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_INVALID_ARGUMENT);
    d.shape_count = f.K;
    shapes[f.K + 1] = kNaN;
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_INVALID_ARGUMENT);
    shapes[f.K + 1] = 0.f;
    std::vector<float> poses(n * 4ull * f.J, 0.f);  // zero quaternions
    d.poses = poses.data();
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_INVALID_ARGUMENT);
    d.poses = nullptr;
    d.pose_format = static_cast<ssc_rotation_format>(7);
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_INVALID_ARGUMENT);
    d.pose_format = SSC_ROTATION_QUATERNION;
    d.vertices = nullptr;
    CHECK(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(untouched(verts));
    d.vertices = verts.data();
    REQUIRE(ssc_model_synthesize_batch(f.model.get(), &d) == SSC_OK);
    CHECK(!untouched(verts));
}

namespace {
struct Counting {
    std::atomic<long> live{0}, total{0};
};
void* count_alloc(void* user, size_t size, size_t align) {
    auto* c = static_cast<Counting*>(user);
    ++c->live;
    ++c->total;
    return std::aligned_alloc(align, (size + align - 1) / align * align);
}
void count_free(void* user, void* p) {
    --static_cast<Counting*>(user)->live;
    std::free(p);
}
std::vector<std::string>* g_log_sink = nullptr;  // test-only: collects log lines
}  // namespace

TEST_CASE("the context's allocator and log callbacks are used, and handles release in any order", "[api]") {
    Counting counting;
    std::vector<std::string> lines;
    g_log_sink = &lines;
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    def.alloc = count_alloc;
    def.free = count_free;
    def.alloc_user = &counting;
    def.log = [](void*, ssc_log_level, const char* msg) { g_log_sink->push_back(msg); };
    def.log_level = SSC_LOG_DEBUG;
    ssc_context* ctx = nullptr;
    REQUIRE(ssc_context_create(&def, &ctx) == SSC_OK);
    const auto bytes = test::mini_bytes();
    ssc_model* m = nullptr;
    REQUIRE(ssc_model_load_memory(ctx, bytes.data(), bytes.size(), &m) == SSC_OK);
    ssc_body* b = nullptr;
    REQUIRE(ssc_body_create(m, nullptr, &b) == SSC_OK);
    CHECK(counting.total > 10);  // model and body arrays came from our allocator
    CHECK(!lines.empty());
    CHECK(lines.back().find("loaded model") != std::string::npos);
    // Release in the "wrong" order: context, model, then body.
    ssc_context_destroy(ctx);
    ssc_model_release(m);
    CHECK(ssc_model_vertex_count(m) == 300);  // the body still holds the model
    ssc_body_destroy(b);
    CHECK(counting.live == 0);
    g_log_sink = nullptr;
}
