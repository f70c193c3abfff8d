#include "registration/landmark_agreement.hpp"

#include "common/error.hpp"
#include "fitting/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <unordered_map>

namespace ssc::registration {

namespace {

std::string millimetres(double metres) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f mm", metres * 1e3);
    return text;
}

// The model's landmark of the other side ("Lt. Acromion" <-> "Rt. Acromion"), or -1.
int64_t other_side(const format::ModelData& model, uint32_t l, const std::unordered_map<std::string, uint32_t>& by_name) {
    const std::string& name = model.landmarks[l].name;
    if (name.size() < 3 || (name.compare(0, 3, "Lt.") != 0 && name.compare(0, 3, "Rt.") != 0)) return -1;
    const auto it = by_name.find((name[0] == 'L' ? "Rt." : "Lt.") + name.substr(3));
    return it == by_name.end() ? -1 : int64_t(it->second);
}

}  // namespace

Eigen::Vector3d point_on(const std::vector<Eigen::Vector3d>& vertices, const fitting::SurfacePoint& p) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i)
        if (p.weight[i] != 0) x += p.weight[i] * vertices[p.vertex[i]];
    return x;
}

void require_landmarks_on_scan(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks,
                               const fitting::PointIndex& scan) {
    std::string far;
    std::size_t count = 0;
    for (const auto& l : landmarks) {
        double d2 = 0;
        scan.nearest(l.position, &d2);
        if (std::sqrt(d2) <= kLandmarkOffScan) continue;
        if (++count <= 3) far += (far.empty() ? "" : ", ") + model.landmarks[l.landmark].name + " " + millimetres(std::sqrt(d2));
    }
    if (count)
        fail(SSC_ERROR_INVALID_ARGUMENT, "register: " + std::to_string(count) + " of " + std::to_string(landmarks.size()) +
                                             " landmarks lie farther than 30 cm from every scan point (" + far + (count > 3 ? ", ..." : "") +
                                             "): they are not on this scan (another scan's, another frame or units, or misplaced)");
}

LandmarkAgreement landmark_agreement(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks,
                                     const std::vector<Eigen::Vector3d>& fitted) {
    LandmarkAgreement a;
    std::unordered_map<std::string, uint32_t> by_name;
    for (uint32_t l = 0; l < model.landmarks.size(); ++l) by_name[model.landmarks[l].name] = l;
    double as_given = 0, exchanged = 0;
    std::size_t sided = 0;
    for (const auto& l : landmarks) {
        const double r = (point_on(fitted, fitting::landmark_point(model, l.landmark)) - l.position).norm();
        a.residual.push_back(r);
        a.off.push_back(r > kLandmarkOff ? 1 : 0);
        a.off_count += r > kLandmarkOff;
        const int64_t other = other_side(model, l.landmark, by_name);
        if (other < 0) continue;
        as_given += r;
        exchanged += (point_on(fitted, fitting::landmark_point(model, uint32_t(other))) - l.position).norm();
        ++sided;
    }
    // Exchanged, the sided landmarks would sit where the body has the other side's: far closer.
    a.swapped = sided >= 4 && exchanged < 0.3 * as_given;
    return a;
}

std::string LandmarkAgreement::describe(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks) const {
    std::vector<std::size_t> order(residual.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return residual[i] > residual[j]; });
    std::string worst;
    for (std::size_t k = 0; k < std::min<std::size_t>(3, off_count); ++k)
        worst += (k ? ", " : "") + model.landmarks[landmarks[order[k]].landmark].name + " " + millimetres(residual[order[k]]);
    std::string text = std::to_string(off_count) + " of " + std::to_string(residual.size()) +
                       " landmarks lie more than 6 cm from where the model fitted to the scan has them (" + worst + (off_count > 3 ? ", ..." : "") + ")";
    return text + (swapped ? ": left and right are exchanged (the Lt. landmarks are on the body's right)" : ": they disagree with the scan (moved, or another scan's)");
}

}  // namespace ssc::registration
