#include "body_inputs.hpp"

#include "cli.hpp"

#include "common/files.hpp"

#include <sscape/sscape_offline.h>

#include <nlohmann/json.hpp>

#include <algorithm>

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
    const std::string text = read_regular_file(path, 16u << 20, SSC_ERROR_INVALID_ARGUMENT);
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw UsageError(path + ": not a JSON object (write one with sscape fit --params)");
    FitParams p;
    try {
        // Parameters mean something only in the model they were fitted with: with another one they
        // once made another body (31 mm RMS away) without a word.
        const char *digest = "", *name = "";
        check(ssc_model_get_digest(model, &digest), "model digest");
        check(ssc_model_get_metadata(model, SSC_METADATA_NAME, &name), "model name");
        const std::string given_name = j.value("model", std::string()), given_digest = j.value("model_digest", std::string());
        if ((!given_digest.empty() && given_digest != digest) || (given_digest.empty() && !given_name.empty() && given_name != name))
            throw std::runtime_error(path + " was fitted with the model '" + given_name + "'" + (given_digest.empty() ? "" : " (digest " + given_digest + ")") +
                                     ", not this one ('" + name + "', digest " + digest + "): give that model (sscape synth MODEL --params " + path + ")");
        p.shape = j.at("shape").get<std::vector<float>>();
        const auto& frame = j.at("frames").at(0);
        p.translation = frame.at("translation_m").get<std::vector<float>>();
        if (p.translation.size() != 3) throw UsageError(path + ": translation_m needs 3 numbers");
        if (frame.contains("scale") && frame.at("scale").get<double>() != 1.0)
            throw UsageError(path + ": the fit has a scale other than 1 (--scale), which a body does not have");
        const uint32_t J = ssc_model_joint_count(model);
        p.pose.assign(4ull * J, 0.f);
        for (uint32_t k = 0; k < J; ++k) p.pose[4 * k + 3] = 1.f;
        for (const auto& [name, q] : frame.at("rotations_xyzw").items()) {
            uint32_t k = 0;
            if (ssc_model_find_joint(model, name.c_str(), &k) != SSC_OK) throw UsageError(path + ": the model has no joint '" + name + "'");
            const auto v = q.get<std::vector<float>>();
            if (v.size() != 4) throw UsageError(path + ": the rotation of " + name + " needs 4 numbers (x y z w)");
            for (int c = 0; c < 4; ++c) p.pose[4 * k + uint32_t(c)] = v[std::size_t(c)];
        }
    } catch (const nlohmann::json::exception& e) {
        throw UsageError(path + ": " + e.what() + " (expected sscape fit --params output)");
    }
    return p;
}

}  // namespace ssc::cli
