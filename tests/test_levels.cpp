// Levels of detail (issue 49): the file's DetailLevel, its validation, synthesis of a level through
// the C API (exact in shape, posed by the level's own skin), and the trained levels of the default
// model and of the MakeHuman proxies.
#include "support.hpp"

#include "common/files.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <random>

#include "training/closest_on_mesh.hpp"
#include "training/makehuman/assets.hpp"
#include "training/makehuman/proxy.hpp"

using namespace ssc;

namespace {

// A level of the mini model: its own triangles over every vertex, each level vertex the body vertex
// (weight 1) for even vertices and an affine mix of four for odd ones, the mixed skin of the sources.
format::DetailLevel mini_level(const format::ModelData& m) {
    format::DetailLevel l;
    l.name = "mini";
    const uint32_t V = m.vertex_count();
    l.vertex_count = V;
    for (uint32_t v = 0; v < V; ++v) {
        const uint32_t a = v, b = (v + 1) % V, c = (v + 2) % V, d = (v + 3) % V;
        const bool mixed = v % 2 == 1;
        l.sources.insert(l.sources.end(), {a, b, c, d});
        if (mixed) l.source_weights.insert(l.source_weights.end(), {0.7f, 0.2f, 0.3f, -0.2f});
        else l.source_weights.insert(l.source_weights.end(), {1.f, 0.f, 0.f, 0.f});
        for (int k = 0; k < 4; ++k) l.skin_joints.push_back(m.skin.joints[4 * std::size_t(v) + std::size_t(k)]), l.skin_weights.push_back(m.skin.weights[4 * std::size_t(v) + std::size_t(k)]);
    }
    l.triangles.assign(m.mesh.triangles.begin(), m.mesh.triangles.end());
    for (std::size_t i = 0; i < m.landmarks.size(); ++i) {
        l.landmark_triangles.push_back(uint32_t(i % l.triangle_count()));
        l.landmark_barycentric.insert(l.landmark_barycentric.end(), {0.2f, 0.3f, 0.5f});
    }
    return l;
}

ssc_status load_with(const std::function<void(format::ModelData&)>& change, std::string* message = nullptr) {
    auto built = test::mini_model();
    built.data.levels.push_back(mini_level(built.data));
    change(built.data);
    format::WriteOptions o;
    o.validate = false;
    ssc_model* m = nullptr;
    const std::vector<unsigned char> bytes = format::write_model(built.data, o);
    const ssc_status s = ssc_model_load_memory(nullptr, bytes.data(), bytes.size(), &m);
    if (message) *message = ssc_last_error();
    ssc_model_release(m);
    return s;
}

std::vector<float> level_floats(ssc_status (*get)(ssc_body*, uint32_t, float*, uint32_t, size_t), ssc_body* body, uint32_t level, uint32_t n) {
    std::vector<float> out(3ull * n, std::nanf(""));
    REQUIRE(get(body, level, out.data(), n, 0) == SSC_OK);
    return out;
}

}  // namespace

TEST_CASE("a level of detail is written, read back and checked", "[levels]") {
    auto built = test::mini_model();
    built.data.levels.push_back(mini_level(built.data));
    const format::ModelData back = format::read_model(format::write_model(built.data).data(), format::write_model(built.data).size());
    REQUIRE(back.levels.size() == 1);
    CHECK(back.levels[0].name == "mini");
    CHECK(back.levels[0].sources == built.data.levels[0].sources);
    CHECK(back.levels[0].source_weights == built.data.levels[0].source_weights);
    CHECK(back.levels[0].triangles == built.data.levels[0].triangles);
    CHECK(back.levels[0].skin_weights == built.data.levels[0].skin_weights);
    CHECK(back.levels[0].landmark_barycentric == built.data.levels[0].landmark_barycentric);
    CHECK(back.levels[0].uvs.empty());

    std::string msg;
    CHECK(load_with([](auto&) {}) == SSC_OK);
    CHECK(load_with([](auto& m) { m.levels[0].sources[5] = m.mesh.vertex_count; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("level 'mini'.sources") != std::string::npos);
    CHECK(load_with([](auto& m) { m.levels[0].source_weights[4] += 0.1f; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("do not sum to 1") != std::string::npos);
    CHECK(load_with([](auto& m) { m.levels[0].source_weights[4] = std::numeric_limits<float>::quiet_NaN(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].source_weights[4] = 40.f, m.levels[0].source_weights[5] = -39.f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].triangles[2] = m.levels[0].vertex_count; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].triangles.pop_back(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].vertex_count += 1; }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("sources") != std::string::npos);
    CHECK(load_with([](auto& m) { m.levels[0].vertex_count = 0xFFFFFFFFu; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].skin_joints[0] = uint16_t(m.joint_count()); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].skin_weights[0] = -0.5f, m.levels[0].skin_weights[1] += 0.5f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].landmark_triangles.pop_back(); }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].landmark_triangles[0] = 1u << 30; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].landmark_barycentric[0] = 2.f; }) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(load_with([](auto& m) { m.levels[0].uvs = {0.f, 0.f}; }) == SSC_ERROR_MODEL_CORRUPT);  // UVs without triangle_uvs
    CHECK(load_with([](auto& m) { m.levels.push_back(m.levels[0]); }, &msg) == SSC_ERROR_MODEL_CORRUPT);
    CHECK(msg.find("levels") != std::string::npos);
    CHECK(load_with([](auto& m) { m.levels[0].name.clear(); }) == SSC_ERROR_MODEL_CORRUPT);
}

TEST_CASE("a level follows the body's shape exactly and its skin poses it", "[levels]") {
    auto built = test::mini_model();
    built.data.levels.push_back(mini_level(built.data));
    // The mixed level vertices' own skin: what an engine uses; the identity ones pose exactly.
    const test::ModelPtr model = test::load(format::write_model(built.data));
    REQUIRE(model);
    const test::BodyPtr body = test::body(model.get());
    REQUIRE(ssc_model_level_count(model.get()) == 2);
    ssc_level_info info{};
    info.struct_size = sizeof info;
    REQUIRE(ssc_model_get_level_info(model.get(), 1, &info) == SSC_OK);
    CHECK(std::string(info.name) == "mini");
    const uint32_t V = ssc_model_vertex_count(model.get()), N = info.vertex_count;
    REQUIRE(ssc_model_get_level_info(model.get(), 0, &info) == SSC_OK);
    CHECK(std::string(info.name) == "full");
    CHECK(info.vertex_count == V);
    std::vector<uint32_t> src(4ull * N);
    std::vector<float> w(4ull * N);
    REQUIRE(ssc_model_get_level_sources(model.get(), 1, src.data(), w.data(), N) == SSC_OK);

    std::mt19937 rng(3);
    std::normal_distribution<float> g(0, 1);
    for (int trial = 0; trial < 3; ++trial) {
        std::vector<float> shape(ssc_model_shape_count(model.get()));
        for (float& c : shape) c = g(rng);
        REQUIRE(ssc_body_set_shape(body.get(), shape.data(), uint32_t(shape.size())) == SSC_OK);
        std::vector<float> pose(4ull * ssc_model_joint_count(model.get()), 0.f);
        for (std::size_t j = 0; j < pose.size(); j += 4) {
            const float ax = 0.3f * g(rng), ay = 0.3f * g(rng), az = 0.3f * g(rng), a = std::sqrt(ax * ax + ay * ay + az * az);
            const float s = a > 0 ? std::sin(a / 2) / a : 0;
            pose[j] = ax * s, pose[j + 1] = ay * s, pose[j + 2] = az * s, pose[j + 3] = std::cos(a / 2);
        }
        REQUIRE(ssc_body_set_pose(body.get(), pose.data(), uint32_t(pose.size() / 4), nullptr) == SSC_OK);
        const std::vector<float> rest = test::rest(model.get(), body.get()), posed = test::posed(model.get(), body.get());
        const std::vector<float> level_rest = level_floats(ssc_body_get_level_rest_vertices, body.get(), 1, N);
        const std::vector<float> level_posed = level_floats(ssc_body_get_level_vertices, body.get(), 1, N);
        const std::vector<float> normals = level_floats(ssc_body_get_level_normals, body.get(), 1, N);
        for (uint32_t i = 0; i < N; ++i) {
            for (uint32_t a = 0; a < 3; ++a) {
                double mapped = 0;
                for (uint32_t k = 0; k < 4; ++k) mapped += double(w[4 * i + k]) * rest[3ull * src[4 * i + k] + a];
                REQUIRE(std::abs(level_rest[3 * i + a] - mapped) < 1e-5);
                if (i % 2 == 0) REQUIRE(std::abs(level_posed[3 * i + a] - posed[3ull * i + a]) < 1e-5);  // one source: exact
            }
            const double n = std::hypot(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
            REQUIRE(std::abs(n - 1) < 1e-4);
        }
    }
    // Level 0 is the full mesh.
    const std::vector<float> full = level_floats(ssc_body_get_level_vertices, body.get(), 0, V);
    CHECK(full == test::posed(model.get(), body.get()));
    // Bad calls: an unknown level, a small buffer (nothing written), NULL.
    std::vector<float> small(3ull * (N - 1), 7.f);
    CHECK(ssc_body_get_level_vertices(body.get(), 2, small.data(), N, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("level 2") != std::string::npos);
    CHECK(ssc_body_get_level_vertices(body.get(), 1, small.data(), N - 1, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(std::all_of(small.begin(), small.end(), [](float x) { return x == 7.f; }));
    CHECK(ssc_body_get_level_vertices(nullptr, 1, small.data(), N, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_level_info(model.get(), 5, &info) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_level_uvs(model.get(), 1, small.data(), N) == SSC_ERROR_NOT_FOUND);
    CHECK(ssc_model_level_count(nullptr) == 0);
}

TEST_CASE("the default model's levels of detail: the simplified template and the MakeHuman proxies", "[levels]") {
    test::DefaultBody b;
    const uint32_t L = ssc_model_level_count(b.model);
    REQUIRE(L == 4);
    const char* names[] = {"full", "simplified", "female1605", "proxy741"};
    std::vector<float> pose(4ull * ssc_model_joint_count(b.model));
    REQUIRE(ssc_model_get_named_pose(b.model, "sitting", pose.data(), ssc_model_joint_count(b.model)) == SSC_OK);
    REQUIRE(ssc_body_set_pose(b.body, pose.data(), ssc_model_joint_count(b.model), nullptr) == SSC_OK);
    const std::vector<float> posed = test::posed(b.model, b.body);
    std::vector<float> full_landmarks(3ull * ssc_model_landmark_count(b.model));
    REQUIRE(ssc_body_get_landmarks(b.body, full_landmarks.data(), ssc_model_landmark_count(b.model), 0) == SSC_OK);
    for (uint32_t l = 0; l < L; ++l) {
        ssc_level_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_level_info(b.model, l, &info) == SSC_OK);
        INFO("level " << l << " " << info.name);
        CHECK(std::string(info.name) == names[l]);
        CHECK(info.uv_count > 0);
        const uint32_t N = info.vertex_count;
        if (l == 1) CHECK((N > 3600 && N < 4400));
        if (l == 2) CHECK(N == 1605);
        if (l == 3) CHECK(N == 741);
        std::vector<uint16_t> joints(4ull * N);
        std::vector<float> weights(4ull * N);
        REQUIRE(ssc_model_get_level_skin(b.model, l, joints.data(), weights.data(), N) == SSC_OK);
        // Posed by its own skin (as an engine poses it), a level stays where its map of the posed
        // full mesh lies: within 0.5 mm on average, a few centimetres at worst where a proxy's
        // blended skin bends a joint otherwise (measured: 0.07 and 0.13 mm mean, 12 and 13 mm worst
        // over the named poses; the simplified level exactly).
        std::vector<uint32_t> src(4ull * N);
        std::vector<float> w(4ull * N);
        REQUIRE(ssc_model_get_level_sources(b.model, l, src.data(), w.data(), N) == SSC_OK);
        const std::vector<float> level = level_floats(ssc_body_get_level_vertices, b.body, l, N);
        double mean = 0, worst = 0;
        for (uint32_t i = 0; i < N; ++i) {
            double d2 = 0;
            for (uint32_t a = 0; a < 3; ++a) {
                double mapped = 0;
                for (uint32_t k = 0; k < 4; ++k) mapped += double(w[4 * i + k]) * posed[3ull * src[4 * i + k] + a];
                d2 += (level[3 * i + a] - mapped) * (level[3 * i + a] - mapped);
            }
            mean += std::sqrt(d2) / N, worst = std::max(worst, std::sqrt(d2));
        }
        CHECK(mean < 0.0005);
        CHECK(worst < 0.03);
        if (l <= 1) CHECK(worst < 1e-5);
        // Its landmarks, on its own triangles, lie where the full mesh's are: within 3 cm on these
        // coarse meshes (a proxy's nose or nipple is a few triangles).
        if (l == 0) continue;
        const format::DetailLevel& data = test::default_cpp_model().level(l - 1);
        double landmark_worst = 0;
        for (std::size_t k = 0; k < full_landmarks.size() / 3; ++k) {
            const uint32_t t = data.landmark_triangles[k];
            double d2 = 0;
            for (uint32_t a = 0; a < 3; ++a) {
                double x = 0;
                for (uint32_t c = 0; c < 3; ++c) x += double(data.landmark_barycentric[3 * k + c]) * level[3ull * data.triangles[3ull * t + c] + a];
                d2 += (x - full_landmarks[3 * k + a]) * (x - full_landmarks[3 * k + a]);
            }
            landmark_worst = std::max(landmark_worst, std::sqrt(d2));
        }
        INFO("landmarks' worst distance " << landmark_worst * 1e3 << " mm");
        CHECK(landmark_worst < 0.05);
    }
}

TEST_CASE("every level of detail goes into one glTF file, a node each on the one skeleton", "[levels][io]") {
    test::DefaultBody b;
    const std::string folder = test::fresh_folder("levels", "glb");
    const std::string glb = folder + "/all.glb", obj = folder + "/all.obj";
    REQUIRE(ssc_body_write_level_file(b.body, SSC_LEVEL_ALL, glb.c_str(), SSC_FILE_FORMAT_BY_EXTENSION) == SSC_OK);
    const std::string bytes = ssc::read_regular_file(glb, 64u << 20);
    REQUIRE(bytes.size() > 20);
    const uint32_t json_length = uint32_t(uint8_t(bytes[12])) | uint32_t(uint8_t(bytes[13])) << 8 | uint32_t(uint8_t(bytes[14])) << 16 |
                                 uint32_t(uint8_t(bytes[15])) << 24;
    const nlohmann::json doc = nlohmann::json::parse(bytes.substr(20, json_length));
    REQUIRE(doc["meshes"].size() == ssc_model_level_count(b.model));
    std::vector<std::string> mesh_nodes;
    for (const auto& node : doc["nodes"])
        if (node.contains("mesh")) {
            mesh_nodes.push_back(node["name"]);
            CHECK(node["skin"] == 0);
        }
    CHECK(mesh_nodes == std::vector<std::string>{"sscape-default_LOD0", "sscape-default_LOD1", "sscape-default_LOD2", "sscape-default_LOD3"});
    REQUIRE(doc["materials"].size() == 1);
    CHECK(doc["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] == 0.0);
    CHECK(doc["materials"][0]["pbrMetallicRoughness"].contains("baseColorTexture"));  // the UVs are used
    // Every level's accessor counts: the level's vertices split at its UV seams, never fewer.
    for (uint32_t l = 0; l < ssc_model_level_count(b.model); ++l) {
        ssc_level_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_level_info(b.model, l, &info) == SSC_OK);
        const int position = doc["meshes"][l]["primitives"][0]["attributes"]["POSITION"];
        CHECK(doc["accessors"][position]["count"].get<uint32_t>() >= info.vertex_count);
    }
    // Not in OBJ or PLY (one mesh a file), and nothing written.
    CHECK(ssc_body_write_level_file(b.body, SSC_LEVEL_ALL, obj.c_str(), SSC_FILE_FORMAT_BY_EXTENSION) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("glTF") != std::string::npos);
    CHECK(!std::filesystem::exists(obj));
    CHECK(ssc_body_write_level_file(b.body, 9, glb.c_str(), SSC_FILE_GLB) == SSC_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("MakeHuman proxy meshes are read, bound to the body and refused when malformed", "[levels][training]") {
    const std::string root = test::makehuman_root();
    if (root.empty()) {
        WARN("SKIPPED: the MakeHuman assets are not there (SSCAPE_MAKEHUMAN)");
        return;
    }
    const std::string dir = root + "/makehuman-assets/base/proxymeshes/";
    const training::mh::Proxy p = training::mh::read_proxy(dir + "proxy741/proxy741.proxy", 19158);
    CHECK(p.vertex_count() == 741);
    CHECK(p.triangles.size() == 3 * 1460);
    CHECK(p.uvs.size() == 2 * 972);
    // A proxy bound to the helper geometry beyond the body's vertices: rebound to the body.
    const training::mh::Proxy f = training::mh::read_proxy(dir + "female1605/female1605.proxy", 19158);
    bool helper = false;
    for (const auto& r : f.refs) helper |= r[0] >= training::mh::kBodyVertices || r[1] >= training::mh::kBodyVertices || r[2] >= training::mh::kBodyVertices;
    CHECK(helper);
    const Model& m = test::default_cpp_model();
    for (const auto& level : m.data().levels)
        for (uint32_t s : level.sources) REQUIRE(s < m.vertex_count());

    // Hostile proxies: an index past the base mesh, a line that is no binding and ends the list
    // early (the obj then has more vertices), no obj, no scales.
    const std::string folder = test::fresh_folder("levels", "proxies");
    auto write = [&](const std::string& name, const std::string& text) {
        std::ofstream(folder + "/" + name) << text;
        return folder + "/" + name;
    };
    write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    const std::string head = "name tri\nobj_file tri.obj\nx_scale 1 2 1.0\ny_scale 1 2 1.0\nz_scale 1 2 1.0\nverts 0\n";
    CHECK(training::mh::read_proxy(write("ok.proxy", head + "0\n1\n2 3 4 0.2 0.3 0.5 0 0 0\n"), 100).vertex_count() == 3);
    CHECK_THROWS_WITH(training::mh::read_proxy(write("far.proxy", head + "0\n1\n200\n"), 100), Catch::Contains("line 9") && Catch::Contains("out of range"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("short.proxy", head + "0\n1\n"), 100), Catch::Contains("has 3 vertices, its proxy binds 2"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("noobj.proxy", "x_scale 1 2 1\ny_scale 1 2 1\nz_scale 1 2 1\nverts 0\n0\n"), 100), Catch::Contains("obj_file"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("noscale.proxy", "obj_file tri.obj\nverts 0\n0\n1\n2\n"), 100), Catch::Contains("x_scale"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("nan.proxy", head + "0\n1\n2 3 4 nan 0.3 0.5 0 0 0\n"), 100), Catch::Contains("line 9") && Catch::Contains("'nan' is not a finite number"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("eight.proxy", head + "0\n1\n2 3 4 0.2 0.3 0.5 0 0\n"), 100), Catch::Contains("a binding is one base vertex or 9 numbers"));
    CHECK_THROWS_WITH(training::mh::read_proxy(write("huge.proxy", head + "0\n1\n2 3 4 1e300 0.3 0.5 0 0 0\n"), 100), Catch::Contains("out of range"));
}

TEST_CASE("batch synthesis of a level of detail gives what a body gives", "[levels][batch]") {
    test::DefaultBody b;
    const uint32_t K = ssc_model_shape_count(b.model), J = ssc_model_joint_count(b.model), n = 5;
    std::vector<float> shapes(std::size_t(n) * K), poses(std::size_t(n) * 4 * J), translations(3 * n);
    REQUIRE(ssc_model_sample_shapes(b.model, 11, n, 2.5f, shapes.data(), uint32_t(shapes.size())) == SSC_OK);
    const char* names[] = {"sitting", "arms_raised", "t_pose", "crouching", "a_pose"};
    for (uint32_t i = 0; i < n; ++i) {
        REQUIRE(ssc_model_get_named_pose(b.model, names[i], &poses[std::size_t(i) * 4 * J], J) == SSC_OK);
        translations[3 * i] = 0.1f * float(i);
    }
    for (uint32_t level = 1; level < ssc_model_level_count(b.model); ++level) {
        ssc_level_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_level_info(b.model, level, &info) == SSC_OK);
        const uint32_t N = info.vertex_count;
        std::vector<float> vertices(3ull * n * N), normals(3ull * n * N);
        ssc_batch_desc d;
        ssc_batch_desc_init(&d, sizeof d);
        d.body_count = n;
        d.shapes = shapes.data();
        d.shape_count = K;
        d.poses = poses.data();
        d.translations = translations.data();
        d.vertices = vertices.data();
        d.vertices_capacity = std::size_t(n) * N;
        d.normals = normals.data();
        d.normals_capacity = std::size_t(n) * N;
        d.level = level;
        REQUIRE(ssc_model_synthesize_batch(b.model, &d) == SSC_OK);
        double worst = 0, worst_normal = 0;
        std::vector<float> one(3ull * N), one_normals(3ull * N);
        for (uint32_t i = 0; i < n; ++i) {
            REQUIRE(ssc_body_set_shape(b.body, &shapes[std::size_t(i) * K], K) == SSC_OK);
            REQUIRE(ssc_body_set_pose(b.body, &poses[std::size_t(i) * 4 * J], J, &translations[3 * i]) == SSC_OK);
            REQUIRE(ssc_body_get_level_vertices(b.body, level, one.data(), N, 0) == SSC_OK);
            REQUIRE(ssc_body_get_level_normals(b.body, level, one_normals.data(), N, 0) == SSC_OK);
            for (std::size_t k = 0; k < 3ull * N; ++k) {
                worst = std::max(worst, double(std::abs(one[k] - vertices[3ull * N * i + k])));
                worst_normal = std::max(worst_normal, double(std::abs(one_normals[k] - normals[3ull * N * i + k])));
            }
        }
        INFO("level " << level);
        CHECK(worst < 1e-6);
        CHECK(worst_normal < 1e-5);
        // The level's size, not the full mesh's: one vertex short is refused, outputs untouched.
        d.vertices_capacity = std::size_t(n) * N - 1;
        std::fill(vertices.begin(), vertices.end(), -7.f);
        CHECK(ssc_model_synthesize_batch(b.model, &d) == SSC_ERROR_BUFFER_TOO_SMALL);
        CHECK(vertices[0] == -7.f);
    }
    ssc_batch_desc d;
    ssc_batch_desc_init(&d, sizeof d);
    CHECK(d.level == 0);
    d.body_count = 1;
    d.level = ssc_model_level_count(b.model);
    std::vector<float> out(3ull * ssc_model_vertex_count(b.model));
    d.vertices = out.data();
    d.vertices_capacity = ssc_model_vertex_count(b.model);
    CHECK(ssc_model_synthesize_batch(b.model, &d) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("level") != std::string::npos);
}

TEST_CASE("the closest point on a mesh is found exactly as a scan of every triangle finds it", "[levels][training]") {
    const format::ModelData& m = test::default_cpp_model().data();
    const std::vector<float> xyz(m.shape.mean.begin(), m.shape.mean.end());  // the mean body
    const std::vector<uint32_t> triangles(m.mesh.triangles.begin(), m.mesh.triangles.end());
    const training::MeshClosest closest(xyz, triangles);
    const auto scan_all = [&](const Eigen::Vector3d& p) {
        double best = std::numeric_limits<double>::infinity();
        std::pair<uint32_t, std::array<double, 3>> out{0, {1, 0, 0}};
        for (uint32_t f = 0; 3 * std::size_t(f) < triangles.size(); ++f) {
            Eigen::Vector3d c[3];
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) c[k][a] = xyz[3 * std::size_t(triangles[3 * std::size_t(f) + std::size_t(k)]) + std::size_t(a)];
            const std::array<double, 3> w = training::closest_barycentric(p, c[0], c[1], c[2]);
            const double d = (w[0] * c[0] + w[1] * c[1] + w[2] * c[2] - p).squaredNorm();
            if (d < best) best = d, out = {f, w};
        }
        return out;
    };
    // Points near the surface (vertices moved up to 3 cm), far from it (up to a metre), and a vertex itself.
    std::mt19937 rng(5);
    std::uniform_int_distribution<uint32_t> vertex(0, m.vertex_count() - 1);
    std::uniform_real_distribution<double> near(-0.03, 0.03), far(-1.0, 1.0);
    for (int i = 0; i < (test::sanitized ? 40 : 200); ++i) {
        const uint32_t v = vertex(rng);
        Eigen::Vector3d p(xyz[3 * std::size_t(v)], xyz[3 * std::size_t(v) + 1], xyz[3 * std::size_t(v) + 2]);
        if (i % 4 == 1) p += Eigen::Vector3d(near(rng), near(rng), near(rng));
        if (i % 4 == 2) p += Eigen::Vector3d(far(rng), far(rng), far(rng));
        const auto expected = scan_all(p), found = closest(p);
        INFO("point " << i << " at vertex " << v);
        CHECK(found.first == expected.first);
        CHECK(found.second == expected.second);
    }
    // A mesh without triangles: triangle 0, its first corner.
    const std::vector<uint32_t> none;
    const training::MeshClosest empty(xyz, none);
    CHECK(empty(Eigen::Vector3d::Zero()).first == 0);
    CHECK(empty(Eigen::Vector3d::Zero()).second == std::array<double, 3>{1, 0, 0});
}
