#include "body_inputs.hpp"

#include "cli.hpp"

#include "capi/cpp_access.hpp"
#include "common/files.hpp"
#include "scan_files/fit_params.hpp"
#include "synthesis/model.hpp"

#include <sscape/sscape_offline.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace ssc::cli {

// "name=value,name=value" (SI units).
std::vector<std::pair<std::string, float>> parse_named(const std::string& text, const std::string& option) {
    std::vector<std::pair<std::string, float>> out;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t end = std::min(text.find(',', at), text.size());
        const std::string item = text.substr(at, end - at);
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError(option + ": '" + item + "' is not NAME=VALUE");
        const std::vector<float> v = parse_floats(item.substr(eq + 1), option + " " + item.substr(0, eq));
        if (v.size() != 1) throw UsageError(option + ": '" + item + "' needs one number");
        out.emplace_back(item.substr(0, eq), v[0]);
        at = end + 1;
    }
    return out;
}

void set_sliders(ssc_model* model, ssc_body* body, const std::vector<std::pair<std::string, float>>& sliders) {
    for (const auto& [name, value] : sliders) {
        uint32_t s = 0;
        if (ssc_model_find_slider(model, name.c_str(), &s) != SSC_OK) {
            std::string known;
            for (uint32_t i = 0; i < ssc_model_slider_count(model); ++i) {
                ssc_slider_info info{};
                info.struct_size = sizeof info;
                check(ssc_model_get_slider_info(model, i, &info), "slider");
                known += std::string(i ? ", " : "") + info.name;
            }
            throw UsageError("--sliders: the model has no slider '" + name + "' (it has: " + (known.empty() ? "none" : known) + ")");
        }
        check(ssc_body_set_slider(body, s, value), "slider " + name);
    }
}

FitParams read_params(ssc_model* model, const std::string& path) {
    return parse_params(model, read_regular_file(path, 16u << 20, SSC_ERROR_INVALID_ARGUMENT), path);
}

FitParams parse_params(ssc_model* model, const std::string& text, const std::string& path) {
    const nlohmann::ordered_json file = nlohmann::ordered_json::parse(text, nullptr, false);
    if (file.is_discarded() || !file.is_object()) throw UsageError(path + ": not a JSON object (write one with sscape fit --params)");
    // A registration's report (sscape register --report) holds its model fit under "fit".
    const bool report = !file.contains("shape") && file.contains("fit") && file.at("fit").is_object();
    const nlohmann::ordered_json& j = report ? file.at("fit") : file;
    const Model& m = model_of(model);
    const char* digest = "";
    check(ssc_model_get_digest(model, &digest), "model digest");
    const std::string other = scan_files::other_model(j, m, digest);
    if (!other.empty()) throw std::runtime_error(path + " was " + other + ": give that model (sscape synth MODEL --params " + path + ")");
    scan_files::FitParams read;
    try {
        read = scan_files::fit_params_from_json(j, m, digest);
    } catch (const Error& e) {
        throw UsageError(path + ": " + e.what() + " (expected sscape fit --params output)");
    } catch (const nlohmann::json::exception& e) {
        throw UsageError(path + ": " + e.what() + " (expected sscape fit --params output)");
    }
    const fitting::FitState& f = read.frames[0];
    if (f.scale != 1.0) throw UsageError(path + ": the fit has a scale other than 1 (--scale), which a body does not have");
    FitParams p;
    for (std::size_t k = 0; k < f.shape.size(); ++k) (k < m.component_count() ? p.shape : p.segment_shape).push_back(float(f.shape[k]));
    for (const Eigen::Quaterniond& q : f.pose) p.pose.insert(p.pose.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    for (int a = 0; a < 3; ++a) p.translation.push_back(float(f.translation[a]));
    return p;
}

void set_fit_segments(ssc_model* model, ssc_body* body, const FitParams& params) {
    if (params.segment_shape.empty()) return;
    std::size_t at = 0;
    for (uint32_t s = 0; s < ssc_model_segment_count(model); ++s) {
        ssc_segment_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_segment_info(model, s, &info), "segment");
        if (at + info.shape_count > params.segment_shape.size()) break;  // the reader checked the count
        check(ssc_body_set_segment_shape(body, s, params.segment_shape.data() + at, info.shape_count), std::string("the fit's segment ") + info.name);
        at += info.shape_count;
    }
}

}  // namespace ssc::cli
