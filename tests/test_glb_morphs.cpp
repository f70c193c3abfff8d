// Shape morph targets in GLB files (ssc_body_export): an engine that sets a target's weight must
// get the body the library makes for that shape, joints included, with nothing but the file.
#include "sscape/sscape.h"
#include "support.hpp"

#include "common/files.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace {

// A GLB's JSON and binary chunk, and its float accessors read back.
struct Glb {
    nlohmann::json doc;
    std::string bin;

    explicit Glb(const std::string& path) {
        const std::string bytes = ssc::read_regular_file(path, 256u << 20);
        REQUIRE(bytes.size() > 28);
        uint32_t json_length = 0, bin_length = 0;
        std::memcpy(&json_length, bytes.data() + 12, 4);
        doc = nlohmann::json::parse(bytes.substr(20, json_length));
        std::memcpy(&bin_length, bytes.data() + 20 + json_length, 4);
        bin = bytes.substr(28 + json_length, bin_length);
    }

    std::vector<float> floats(int accessor) const {
        const auto& a = doc["accessors"][accessor];
        REQUIRE(a["componentType"] == 5126);
        const auto& view = doc["bufferViews"][a["bufferView"].get<int>()];
        const std::size_t width = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : a["type"] == "MAT4" ? 16 : 4;
        std::vector<float> out(width * a["count"].get<std::size_t>());
        REQUIRE(view["byteLength"].get<std::size_t>() == out.size() * 4);
        std::memcpy(out.data(), bin.data() + view["byteOffset"].get<std::size_t>(), out.size() * 4);
        return out;
    }
    const nlohmann::json& primitive(int mesh) const { return doc["meshes"][mesh]["primitives"][0]; }
};

ssc_export_def def_of(uint32_t level, ssc_morphs morphs, uint32_t count) {
    ssc_export_def def;
    ssc_export_def_init(&def, sizeof def);
    def.level = level;
    def.morphs = morphs;
    def.morph_count = count;
    return def;
}

}  // namespace

TEST_CASE("a GLB's shape morph targets give the library's body of the moved shape, joints included", "[io][morphs]") {
    test::DefaultBody b;
    const uint32_t K = ssc_model_shape_count(b.model), J = ssc_model_joint_count(b.model);
    std::vector<float> shape(K, 0.f);
    shape[0] = 1.2f, shape[1] = -0.8f, shape[4] = 0.5f;
    REQUIRE(ssc_body_set_shape(b.body, shape.data(), K) == SSC_OK);
    std::vector<float> pose(4ull * J);
    REQUIRE(ssc_model_get_named_pose(b.model, "sitting", pose.data(), J) == SSC_OK);
    REQUIRE(ssc_body_set_pose(b.body, pose.data(), J, nullptr) == SSC_OK);
    const std::string folder = test::fresh_folder("morphs", "components");
    const ssc_export_def def = def_of(SSC_LEVEL_ALL, SSC_MORPHS_COMPONENTS, 3);
    REQUIRE(ssc_body_export(b.body, (folder + "/morphs.glb").c_str(), &def) == SSC_OK);
    const Glb glb(folder + "/morphs.glb");

    // The same body with component 2 moved by w, written without morph targets: what the targets must give.
    const float w = 0.7f;
    std::vector<float> moved = shape;
    moved[1] += w;
    REQUIRE(ssc_body_set_shape(b.body, moved.data(), K) == SSC_OK);
    REQUIRE(ssc_body_write_level_file(b.body, SSC_LEVEL_ALL, (folder + "/moved.glb").c_str(), SSC_FILE_GLB) == SSC_OK);
    const Glb truth(folder + "/moved.glb");

    const uint32_t levels = ssc_model_level_count(b.model);
    REQUIRE(glb.doc["meshes"].size() == levels);
    for (uint32_t l = 0; l < levels; ++l) {
        INFO("level " << l);
        const auto& mesh = glb.doc["meshes"][l];
        CHECK(mesh["extras"]["targetNames"] == nlohmann::json({"component_1", "component_2", "component_3"}));
        CHECK(mesh["weights"] == nlohmann::json({0.0, 0.0, 0.0}));
        const auto& p = glb.primitive(int(l));
        REQUIRE(p["targets"].size() == 3);
        const std::vector<float> base = glb.floats(p["attributes"]["POSITION"]);
        const std::vector<float> delta = glb.floats(p["targets"][1]["POSITION"]);
        const std::vector<float> expected = truth.floats(truth.primitive(int(l))["attributes"]["POSITION"]);
        REQUIRE(base.size() == expected.size());
        double worst = 0;
        for (std::size_t i = 0; i < base.size(); ++i) worst = std::max(worst, double(std::abs(base[i] + w * delta[i] - expected[i])));
        CHECK(worst < 2e-6);
        // The targets move the body: component 2 is not nothing.
        double largest = 0;
        for (float x : delta) largest = std::max(largest, double(std::abs(x)));
        CHECK(largest > 0.005);
        // Normals to first order: at weight w within a few degrees of the moved body's.
        const std::vector<float> n0 = glb.floats(p["attributes"]["NORMAL"]), dn = glb.floats(p["targets"][1]["NORMAL"]);
        const std::vector<float> n1 = truth.floats(truth.primitive(int(l))["attributes"]["NORMAL"]);
        double cos_sum = 0;
        for (std::size_t i = 0; i < n0.size(); i += 3) {
            double dot = 0, len = 0;
            for (int a = 0; a < 3; ++a) {
                const double x = n0[i + a] + w * dn[i + a];
                dot += x * n1[i + a], len += x * x;
            }
            cos_sum += dot / std::sqrt(len);
        }
        CHECK(cos_sum / double(n0.size() / 3) > 0.999);
    }

    // The model vertex of every glTF vertex of the full mesh: its rest position is that vertex's.
    std::vector<float> rest(3ull * ssc_model_vertex_count(b.model));
    REQUIRE(ssc_body_set_shape(b.body, shape.data(), K) == SSC_OK);
    REQUIRE(ssc_body_get_rest_vertices(b.body, rest.data(), ssc_model_vertex_count(b.model), 0) == SSC_OK);
    const std::vector<float> index = glb.floats(glb.primitive(0)["attributes"]["_MODEL_VERTEX"]);
    const std::vector<float> base = glb.floats(glb.primitive(0)["attributes"]["POSITION"]);
    REQUIRE(index.size() * 3 == base.size());
    CHECK(index.size() > ssc_model_vertex_count(b.model));  // split at the UV seams
    double worst_index = 0;
    for (std::size_t i = 0; i < index.size(); ++i) {
        const auto v = std::size_t(index[i]);
        REQUIRE(v < ssc_model_vertex_count(b.model));
        for (int a = 0; a < 3; ++a) worst_index = std::max(worst_index, double(std::abs(base[3 * i + a] - rest[3 * v + a])));
    }
    CHECK(worst_index == 0);

    // The joints: node translations and inverse bind matrices at weight w, from the extras.
    const auto& extras = glb.doc["skins"][0]["extras"]["sscape_morphs"];
    REQUIRE(extras.size() == 3);
    CHECK(extras[1]["name"] == "component_2");
    CHECK(extras[1]["unit"] == "sd");
    const std::vector<float> node_delta = extras[1]["node_translation"], bind_delta = extras[1]["inverse_bind_translation"];
    REQUIRE(node_delta.size() == 3ull * J);
    const std::vector<float> bind = glb.floats(glb.doc["skins"][0]["inverseBindMatrices"]);
    const std::vector<float> bind_truth = truth.floats(truth.doc["skins"][0]["inverseBindMatrices"]);
    double worst_node = 0, worst_bind = 0, moved_most = 0;
    for (uint32_t j = 0; j < J; ++j)
        for (int a = 0; a < 3; ++a) {
            const float t = glb.doc["nodes"][j]["translation"][a], t_truth = truth.doc["nodes"][j]["translation"][a];
            worst_node = std::max(worst_node, double(std::abs(t + w * node_delta[3 * j + a] - t_truth)));
            worst_bind = std::max(worst_bind, double(std::abs(bind[16 * j + 12 + a] + w * bind_delta[3 * j + a] - bind_truth[16 * j + 12 + a])));
            moved_most = std::max(moved_most, double(std::abs(node_delta[3 * j + a])));
        }
    CHECK(worst_node < 2e-6);
    CHECK(worst_bind < 2e-6);
    CHECK(moved_most > 0.001);
}

TEST_CASE("morph targets for the semantic sliders: one per slider, a standard deviation of its attribute", "[io][morphs]") {
    test::DefaultBody b;
    const uint32_t S = ssc_model_slider_count(b.model);
    REQUIRE(S > 0);
    const std::string path = test::fresh_folder("morphs", "sliders") + "/sliders.glb";
    const ssc_export_def def = def_of(0, SSC_MORPHS_SLIDERS, 0);
    REQUIRE(ssc_body_export(b.body, path.c_str(), &def) == SSC_OK);
    const Glb glb(path);
    const auto& names = glb.doc["meshes"][0]["extras"]["targetNames"];
    REQUIRE(names.size() == S);
    const auto& extras = glb.doc["skins"][0]["extras"]["sscape_morphs"];
    for (uint32_t s = 0; s < S; ++s) {
        ssc_slider_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_slider_info(b.model, s, &info) == SSC_OK);
        CHECK(names[s] == info.name);
        CHECK(extras[s]["kind"] == "slider");
        CHECK(extras[s]["per_weight"].get<double>() > 0);
    }
    // The stature target at weight 1 makes the body taller by about one standard deviation (tens of mm).
    CHECK(names[0] == "stature");
    const std::vector<float> base = glb.floats(glb.primitive(0)["attributes"]["POSITION"]);
    const std::vector<float> delta = glb.floats(glb.primitive(0)["targets"][0]["POSITION"]);
    float lo = 1e9f, hi = -1e9f, lo1 = 1e9f, hi1 = -1e9f;
    for (std::size_t i = 1; i < base.size(); i += 3) {
        lo = std::min(lo, base[i]), hi = std::max(hi, base[i]);
        lo1 = std::min(lo1, base[i] + delta[i]), hi1 = std::max(hi1, base[i] + delta[i]);
    }
    const double gain = double(hi1 - lo1) - double(hi - lo), sd = extras[0]["per_weight"];
    INFO("taller by " << gain * 1e3 << " mm for a standard deviation of " << sd * 1e3 << " mm");
    CHECK(std::abs(gain - sd) < 0.25 * sd);
}

TEST_CASE("bad export options are refused and nothing is written", "[io][morphs]") {
    test::DefaultBody b;
    const std::string folder = test::fresh_folder("morphs", "refused");
    const std::string glb = folder + "/x.glb", obj = folder + "/x.obj";
    const uint32_t K = ssc_model_shape_count(b.model);
    ssc_export_def def = def_of(0, SSC_MORPHS_COMPONENTS, 2);
    CHECK(ssc_body_export(b.body, obj.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);  // morph targets: GLB only
    CHECK(std::string(ssc_last_error()).find("glTF") != std::string::npos);
    def = def_of(0, SSC_MORPHS_COMPONENTS, K + 1);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(0, SSC_MORPHS_COMPONENTS, 0);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(0, SSC_MORPHS_SLIDERS, ssc_model_slider_count(b.model) + 1);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(0, static_cast<ssc_morphs>(7), 1);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(0, SSC_MORPHS_NONE, 3);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(ssc_model_level_count(b.model), SSC_MORPHS_NONE, 0);
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    def = def_of(0, SSC_MORPHS_NONE, 0);
    def.struct_size = 3;
    CHECK(ssc_body_export(b.body, glb.c_str(), &def) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_export(nullptr, glb.c_str(), nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_export(b.body, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(!std::filesystem::exists(glb));
    CHECK(!std::filesystem::exists(obj));
    // NULL options: the defaults, the full mesh without morph targets.
    REQUIRE(ssc_body_export(b.body, glb.c_str(), nullptr) == SSC_OK);
    CHECK(!Glb(glb).primitive(0).contains("targets"));
}
