#include "scan_files/fit_params.hpp"

#include "common/error.hpp"
#include "fitting/observations.hpp"
#include "synthesis/shape_range.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::scan_files {

namespace {

using nlohmann::ordered_json;

// A number of the file, refused (naming it) when not finite or beyond `bound`.
double bounded(const ordered_json& value, double bound, const std::string& what) {
    SSC_REQUIRE_ARG_S(value.is_number(), what << " is " << value.dump() << ", not a number");
    const double v = value.get<double>();
    SSC_REQUIRE_ARG_S(std::isfinite(v) && std::abs(v) <= bound,
                      what << " is " << value.dump() << ", outside [-" << ordered_json(bound).dump() << ", " << ordered_json(bound).dump() << "]");
    return v;
}

std::vector<double> numbers(const ordered_json& j, const char* key, double bound) {
    const ordered_json& a = j.at(key);
    SSC_REQUIRE_ARG_S(a.is_array(), key << " is not an array of numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < a.size(); ++i) out.push_back(bounded(a[i], bound, std::string(key) + "[" + std::to_string(i) + "]"));
    return out;
}

Eigen::Quaterniond unit_rotation(const ordered_json& q, const std::string& joint) {
    SSC_REQUIRE_ARG_S(q.is_array() && q.size() == 4, "the rotation of " << joint << " needs 4 numbers (x y z w)");
    double c[4];
    for (std::size_t i = 0; i < 4; ++i) c[i] = bounded(q[i], 1e6, "the rotation of " + joint);
    const Eigen::Quaterniond r(c[3], c[0], c[1], c[2]);
    SSC_REQUIRE_ARG_S(std::abs(r.norm() - 1) <= 1e-3, "the rotation of " << joint << " is not a unit quaternion (length " << r.norm() << ")");
    return r;
}

// One frame's pose, translation and scale: version 1 and 2 name the joints, the flat layout lists
// every joint's rotation in order.
void read_frame(const ordered_json& j, const Model& model, fitting::FitState& f) {
    const uint32_t J = model.joint_count();
    const std::vector<std::string>& names = model.data().skeleton.joint_names;
    f.pose.assign(J, Eigen::Quaterniond::Identity());
    const ordered_json& rotations = j.at("rotations_xyzw");
    if (rotations.is_object()) {
        for (const auto& [joint, q] : rotations.items()) {
            const auto it = std::find(names.begin(), names.end(), joint);
            SSC_REQUIRE_ARG_S(it != names.end(), "the model has no joint '" << joint << "'");
            f.pose[std::size_t(it - names.begin())] = unit_rotation(q, joint);
        }
    } else {
        SSC_REQUIRE_ARG_S(rotations.is_array() && rotations.size() == 4 * std::size_t(J), "rotations_xyzw needs 4 numbers per joint of the model (" << J << ")");
        for (uint32_t k = 0; k < J; ++k)
            f.pose[k] = unit_rotation(ordered_json{rotations[4 * k], rotations[4 * k + 1], rotations[4 * k + 2], rotations[4 * k + 3]}, names[k]);
    }
    const std::vector<double> t = numbers(j, "translation_m", fitting::kMaxCoordinate);
    SSC_REQUIRE_ARG(t.size() == 3, "translation_m needs 3 numbers");
    f.translation = Eigen::Vector3d(t[0], t[1], t[2]);
    if (j.contains("scale")) {  // a body's scale: what the fitter's --scale finds
        const ordered_json& s = j.at("scale");
        SSC_REQUIRE_ARG_S(s.is_number() && std::isfinite(s.get<double>()) && s.get<double>() >= 0.1 && s.get<double>() <= 10,
                          "scale is " << s.dump() << ", outside [0.1, 10]");
        f.scale = s.get<double>();
    }
}

}  // namespace

ordered_json fit_params_to_json(const Model& model, const std::vector<fitting::FitState>& frames, const std::string& model_digest) {
    SSC_REQUIRE_ARG(!frames.empty(), "fit parameters: no frame");
    const std::vector<double>& shape = frames[0].shape;
    const std::size_t K = std::min<std::size_t>(shape.size(), model.component_count());
    const std::vector<std::string>& names = model.data().skeleton.joint_names;
    ordered_json j;
    j["format"] = kFitParamsFormat;
    j["model"] = model.data().metadata.name;
    if (!model_digest.empty()) j["model_digest"] = model_digest;  // what a reader checks its model against
    j["shape"] = std::vector<double>(shape.begin(), shape.begin() + std::ptrdiff_t(K));
    if (shape.size() > K) j["segment_shape"] = std::vector<double>(shape.begin() + std::ptrdiff_t(K), shape.end());
    ordered_json out = ordered_json::array();
    for (const fitting::FitState& f : frames) {
        ordered_json by_joint = ordered_json::object();
        for (std::size_t k = 0; k < f.pose.size() && k < names.size(); ++k) by_joint[names[k]] = {f.pose[k].x(), f.pose[k].y(), f.pose[k].z(), f.pose[k].w()};
        out.push_back({{"rotations_xyzw", by_joint}, {"translation_m", {f.translation.x(), f.translation.y(), f.translation.z()}}, {"scale", f.scale}});
    }
    j["frames"] = out;
    j["frame"] = "the scan's, turned so that its up axis is +Y, in metres";
    return j;
}

ordered_json fit_to_json(const Model& model, const fitting::FitState& fit, const std::string& model_digest) {
    return fit_params_to_json(model, {fit}, model_digest);
}

FitParams fit_params_from_json(const ordered_json& j, const Model& model, const std::string& model_digest) {
    SSC_REQUIRE_ARG(j.is_object(), "not a JSON object");
    FitParams p;
    const std::string format = j.value("format", std::string());
    SSC_REQUIRE_ARG_S(format.empty() || format == kFitParamsFormat || format == "sscape fit parameters 1",
                      "the format '" << format << "' is not one this sscape reads (" << kFitParamsFormat << " or earlier)");
    p.model_name = j.value("model", std::string());
    p.model_digest = j.value("model_digest", std::string());
    const std::string other = other_model(j, model, model_digest);
    SSC_REQUIRE_ARG(other.empty(), other);
    std::vector<double> shape = numbers(j, "shape", kShapeLimit);
    SSC_REQUIRE_ARG_S(shape.size() <= model.component_count(), "shape needs at most " << model.component_count() << " numbers (the model's components)");
    if (j.contains("segment_shape")) {
        const std::vector<double> segments = numbers(j, "segment_shape", kShapeLimit);
        SSC_REQUIRE_ARG_S(segments.empty() || (shape.size() == model.component_count() && segments.size() == model.segment_coefficient_count()),
                          "segment_shape needs the model's " << model.segment_coefficient_count() << " segment coefficients after its "
                                                             << model.component_count() << " components");
        shape.insert(shape.end(), segments.begin(), segments.end());
    }
    if (format.empty()) {  // the flat layout: one frame at the top level
        p.frames.emplace_back();
        read_frame(j, model, p.frames.back());
    } else {
        const ordered_json& frames = j.at("frames");
        SSC_REQUIRE_ARG(frames.is_array() && !frames.empty() && frames.size() <= 100000, "frames needs 1 to 100000 frames");
        for (const ordered_json& frame : frames) {
            p.frames.emplace_back();
            read_frame(frame, model, p.frames.back());
        }
    }
    for (fitting::FitState& f : p.frames) f.shape = shape;
    return p;
}

std::string other_model(const ordered_json& j, const Model& model, const std::string& model_digest) {
    // Parameters mean something only in the model they were fitted with: with another one they
    // once made another body (31 mm RMS away) without a word.
    if (!j.is_object() || model_digest.empty()) return "";
    const std::string given_name = j.contains("model") && j.at("model").is_string() ? j.at("model").get<std::string>() : "";
    const std::string given_digest = j.contains("model_digest") && j.at("model_digest").is_string() ? j.at("model_digest").get<std::string>() : "";
    const std::string& name = model.data().metadata.name;
    if ((!given_digest.empty() && given_digest != model_digest) || (given_digest.empty() && !given_name.empty() && given_name != name))
        return "fitted with the model '" + given_name + "'" + (given_digest.empty() ? "" : " (digest " + given_digest + ")") + ", not this one ('" + name +
               "', digest " + model_digest + ")";
    return "";
}

fitting::FitState fit_from_json(const ordered_json& j, const Model& model) { return fit_params_from_json(j, model).frames[0]; }

}  // namespace ssc::scan_files
