// `sscape info`: what a model holds (counts, metadata, joints, sliders, component spreads), as text
// or, with --json, as one JSON object for scripts.
#include "cli.hpp"

#include "render/segment_picture.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace ssc::cli {

namespace {

// The segments coloured on the mean body, and each one's first component at -3 and +3 SD.
void draw_segments(ssc_model* model, const std::string& png) {
    const uint32_t S = ssc_model_segment_count(model), V = ssc_model_vertex_count(model), T = ssc_model_triangle_count(model);
    if (S == 0) throw UsageError("--segments-png: the model has no segment shape spaces (sscape learn --segment-components makes them)");
    std::vector<uint32_t> tris(3ull * T);
    check(ssc_model_get_triangles(model, tris.data(), T), "triangles");
    ssc_body* body = nullptr;
    check(ssc_body_create(model, nullptr, &body), "body");
    struct Destroy {
        ssc_body* b;
        ~Destroy() { ssc_body_destroy(b); }
    } destroy{body};
    auto rest = [&] {
        std::vector<float> xyz(3ull * V);
        check(ssc_body_get_rest_vertices(body, xyz.data(), V, 0), "vertices");
        return xyz;
    };
    const std::vector<float> mean = rest();
    std::vector<render::SegmentView> views;
    for (uint32_t s = 0; s < S; ++s) {
        ssc_segment_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_segment_info(model, s, &info), "segment");
        render::SegmentView view;
        view.name = info.name;
        std::vector<uint32_t> vertices(info.vertex_count);
        std::vector<float> weights(info.vertex_count);
        check(ssc_model_get_segment_vertices(model, s, vertices.data(), weights.data(), info.vertex_count), "segment vertices");
        view.weight.assign(V, 0.f);
        for (uint32_t i = 0; i < info.vertex_count; ++i) view.weight[vertices[i]] = weights[i];
        for (const float c : {-3.f, 3.f}) {
            check(ssc_body_set_segment_shape(body, s, &c, 1), "segment shape");
            (c < 0 ? view.minus : view.plus) = rest();
        }
        check(ssc_body_set_segment_shape(body, s, nullptr, 0), "segment shape");
        views.push_back(std::move(view));
    }
    render::write_segment_picture(png, mean, tris, views);
}

int run_info(const std::string& path, bool json, const std::string& segments_png) {
    ssc_model* model = load_model(path);
    Handles guard(model);
    // The file's size and container version (its header's bytes 8-11), or the built-in model's.
    long long size = -1;
    unsigned char header[12] = {};
    if (!path.empty()) {
        std::ifstream f(path, std::ios::binary | std::ios::ate);
        size = static_cast<long long>(f.tellg());
        f.seekg(0);
        f.read(reinterpret_cast<char*>(header), sizeof header);
    } else {
        const void* data = nullptr;
        std::size_t bytes = 0;
        check(ssc_default_model_file(&data, &bytes), "default model");
        size = static_cast<long long>(bytes);
        std::memcpy(header, data, std::min(bytes, sizeof header));
    }
    const std::string version = std::to_string(header[8] | header[9] << 8) + "." + std::to_string(header[10] | header[11] << 8);
    auto meta = [&](ssc_metadata_key k) {
        const char* s = "";
        ssc_model_get_metadata(model, k, &s);
        return std::string(s);
    };
    nlohmann::ordered_json j;
    j["file"] = path.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(path);
    j["file_bytes"] = size;
    j["container_version"] = version;
    j["name"] = meta(SSC_METADATA_NAME);
    j["version"] = meta(SSC_METADATA_VERSION);
    j["license"] = meta(SSC_METADATA_LICENSE);
    j["units"] = meta(SSC_METADATA_UNITS);
    j["axes"] = meta(SSC_METADATA_AXES);
    j["provenance"] = meta(SSC_METADATA_PROVENANCE);
    j["vertices"] = ssc_model_vertex_count(model);
    j["triangles"] = ssc_model_triangle_count(model);
    j["quads"] = ssc_model_quad_count(model);
    j["uvs"] = ssc_model_uv_count(model);
    nlohmann::ordered_json joints = nlohmann::ordered_json::array();
    uint32_t limited = 0;
    for (uint32_t i = 0; i < ssc_model_joint_count(model); ++i) {
        const char* name = "";
        check(ssc_model_get_joint_name(model, i, &name), "joint name");
        ssc_joint_limit l{};
        check(ssc_model_get_joint_limit(model, i, &l), "joint limit");
        limited += l.limited;
        joints.push_back({{"name", name}, {"limited", bool(l.limited)}});
    }
    nlohmann::ordered_json landmarks = nlohmann::ordered_json::array();
    for (uint32_t i = 0; i < ssc_model_landmark_count(model); ++i) {
        const char* name = "";
        check(ssc_model_get_landmark_name(model, i, &name), "landmark name");
        landmarks.push_back(name);
    }
    nlohmann::ordered_json sets = nlohmann::ordered_json::object();
    for (uint32_t i = 0; i < ssc_model_vertex_set_count(model); ++i) {
        const char* name = "";
        uint32_t n = 0;
        check(ssc_model_get_vertex_set(model, i, &name, &n), "vertex set");
        sets[name] = n;
    }
    nlohmann::ordered_json sliders = nlohmann::ordered_json::array();
    for (uint32_t i = 0; i < ssc_model_slider_count(model); ++i) {
        ssc_slider_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_slider_info(model, i, &info), "slider");
        sliders.push_back({{"name", info.name}, {"unit", info.unit}, {"mean", info.mean}, {"minimum", info.minimum}, {"maximum", info.maximum}});
    }
    nlohmann::ordered_json segments = nlohmann::ordered_json::array();
    for (uint32_t i = 0; i < ssc_model_segment_count(model); ++i) {
        ssc_segment_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_segment_info(model, i, &info), "segment");
        segments.push_back({{"name", info.name}, {"components", info.shape_count}, {"vertices", info.vertex_count}});
    }
    nlohmann::ordered_json levels = nlohmann::ordered_json::array();
    for (uint32_t i = 0; i < ssc_model_level_count(model); ++i) {
        ssc_level_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_level_info(model, i, &info), "level");
        levels.push_back({{"level", i}, {"name", info.name}, {"vertices", info.vertex_count}, {"triangles", info.triangle_count}, {"uvs", info.uv_count}});
    }
    const uint32_t K = ssc_model_shape_count(model);
    std::vector<float> sd(K);
    if (K) check(ssc_model_get_shape_stddevs(model, sd.data(), K), "stddevs");
    // (Filled last: a reference into an ordered_json does not survive the next insertion.)
    j["joints"] = joints;
    j["landmarks"] = landmarks;
    j["vertex_sets"] = sets;
    j["sliders"] = sliders;
    j["segments"] = segments;
    j["levels"] = levels;
    j["components"] = K;
    j["stddev_m"] = sd;
    if (!segments_png.empty()) {
        draw_segments(model, segments_png);
        if (!json) std::printf("drew the segments and their first components at -3 and +3 SD to %s\n", segments_png.c_str());
    }
    if (json) {
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }

    std::printf("file:        %s (%lld bytes, %.2f MB, container %s)\n", path.empty() ? "(default model, built into the library)" : path.c_str(),
                size, size / 1e6, version.c_str());
    std::printf("name:        %s\n", meta(SSC_METADATA_NAME).c_str());
    std::printf("version:     %s\n", meta(SSC_METADATA_VERSION).c_str());
    std::printf("license:     %s\n", meta(SSC_METADATA_LICENSE).c_str());
    std::printf("units/axes:  %s, %s\n", meta(SSC_METADATA_UNITS).c_str(), meta(SSC_METADATA_AXES).c_str());
    std::printf("provenance:  %s\n", meta(SSC_METADATA_PROVENANCE).c_str());
    std::printf("vertices:    %u\n", ssc_model_vertex_count(model));
    std::printf("triangles:   %u (quads %u, uvs %u)\n", ssc_model_triangle_count(model), ssc_model_quad_count(model),
                ssc_model_uv_count(model));
    std::printf("joints:      %u\n", ssc_model_joint_count(model));
    std::string line = " ";
    for (const auto& joint : joints) {  // the names, wrapped
        const std::string name = joint["name"];
        if (line.size() + name.size() > 100) std::printf("%s\n", line.c_str()), line = " ";
        line += " " + name;
    }
    std::printf("%s\n", line.c_str());
    std::printf("landmarks:   %u\n", ssc_model_landmark_count(model));
    std::printf("vertex sets:");
    for (const auto& [name, n] : sets.items()) std::printf(" %s(%u)", name.c_str(), n.get<uint32_t>());
    std::printf("\njoint limits: %u joints\nsliders:     %u", limited, ssc_model_slider_count(model));
    for (const auto& s : sliders) {
        const std::string unit = s["unit"];
        std::printf("\n  %-12s %-6s mean %8.3f, population %.3f .. %.3f", s["name"].get<std::string>().c_str(), unit.empty() ? "-" : unit.c_str(),
                    s["mean"].get<double>(), s["minimum"].get<double>(), s["maximum"].get<double>());
    }
    std::printf("\nsegments:    %u", ssc_model_segment_count(model));
    for (const auto& s : segments)
        std::printf("\n  %-12s %u components over %u vertices", s["name"].get<std::string>().c_str(), s["components"].get<uint32_t>(),
                    s["vertices"].get<uint32_t>());
    std::printf("\nlevels of detail: %zu (synth --lod)", levels.size());
    for (const auto& l : levels)
        std::printf("\n  %u %-12s %6u vertices %6u triangles", l["level"].get<uint32_t>(), l["name"].get<std::string>().c_str(),
                    l["vertices"].get<uint32_t>(), l["triangles"].get<uint32_t>());
    std::printf("\ncomponents:  %u\nstddev (m):", K);
    for (uint32_t k = 0; k < K; ++k) std::printf("%s%.4g", k % 10 == 0 ? "\n  " : " ", sd[k]);
    std::printf("\n");
    return 0;
}

}  // namespace

Run add_info(CLI::App& app) {
    struct Options {
        std::string model, segments_png;
        bool json = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("info", "what a model holds: counts, metadata, joint names, landmarks, sliders, component spreads");
    add_model_argument(*c, o->model);
    c->add_flag("--json", o->json, "print one JSON object (for scripts) instead of the text");
    c->add_option("--segments-png", o->segments_png, "draw the segment shape spaces: the segments on the mean body, and each one's first "
                  "component at -3 and +3 SD")
        ->type_name("OUT.png")
        ->check(extension(".png"));
    return [o] { return run_info(o->model, o->json, o->segments_png); };
}

}  // namespace ssc::cli
