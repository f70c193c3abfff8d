#include "body_inputs.hpp"

#include "cli.hpp"

#include "common/files.hpp"

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

namespace {

// A number of a parameter file as a float, refused when not finite or beyond `bound` (a float
// cast of 1e300 is undefined, and a body 1e30 SD out is no body).
float bounded(const nlohmann::json& value, double bound, const std::string& what) {
    const double v = value.get<double>();
    if (!std::isfinite(v) || std::fabs(v) > bound)
        throw UsageError(what + " is " + value.dump() + ", outside [-" + nlohmann::json(bound).dump() + ", " + nlohmann::json(bound).dump() + "]");
    return float(v);
}

}  // namespace

FitParams parse_params(ssc_model* model, const std::string& text, const std::string& path) {
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
        // The bounds are those of a fit (learning's reader of the same fits has them too): shape
        // coefficients within 20 SD, a translation within 1000 km, unit quaternions.
        const auto& shape = j.at("shape");
        const uint32_t K = ssc_model_shape_count(model);
        if (!shape.is_array() || shape.size() > K)
            throw UsageError(path + ": shape needs at most " + std::to_string(K) + " numbers (the model's components)");
        for (std::size_t i = 0; i < shape.size(); ++i) p.shape.push_back(bounded(shape[i], 20.0, path + ": shape[" + std::to_string(i) + "]"));
        const auto& frame = j.at("frames").at(0);
        const auto& translation = frame.at("translation_m");
        if (!translation.is_array() || translation.size() != 3) throw UsageError(path + ": translation_m needs 3 numbers");
        for (const auto& t : translation) p.translation.push_back(bounded(t, 1e6, path + ": translation_m"));
        if (frame.contains("scale") && frame.at("scale").get<double>() != 1.0)
            throw UsageError(path + ": the fit has a scale other than 1 (--scale), which a body does not have");
        const uint32_t J = ssc_model_joint_count(model);
        p.pose.assign(4ull * J, 0.f);
        for (uint32_t k = 0; k < J; ++k) p.pose[4 * k + 3] = 1.f;
        for (const auto& [joint, q] : frame.at("rotations_xyzw").items()) {
            uint32_t k = 0;
            if (ssc_model_find_joint(model, joint.c_str(), &k) != SSC_OK) throw UsageError(path + ": the model has no joint '" + joint + "'");
            if (!q.is_array() || q.size() != 4) throw UsageError(path + ": the rotation of " + joint + " needs 4 numbers (x y z w)");
            double norm = 0;
            for (int c = 0; c < 4; ++c) {
                p.pose[4 * k + uint32_t(c)] = bounded(q[std::size_t(c)], 1.0 + 1e-3, path + ": the rotation of " + joint);
                norm += double(p.pose[4 * k + uint32_t(c)]) * p.pose[4 * k + uint32_t(c)];
            }
            if (std::fabs(std::sqrt(norm) - 1.0) > 1e-3)
                throw UsageError(path + ": the rotation of " + joint + " is not a unit quaternion (length " + std::to_string(std::sqrt(norm)) + ")");
        }
    } catch (const nlohmann::json::exception& e) {
        throw UsageError(path + ": " + e.what() + " (expected sscape fit --params output)");
    }
    return p;
}

}  // namespace ssc::cli
