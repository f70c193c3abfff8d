// The robust losses and the point-to-plane data term, shared by the fitter's stages and the rigid
// start search so both minimise the same cost.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace ssc::fitting {

// A loss value and its IRLS weight rho'(r) / r.
struct Robust {
    double cost, weight;
};

// Huber with threshold k (in sigmas): beyond k a residual counts linearly, so an outlier pulls,
// but boundedly.
inline Robust huber(double r, double k) {
    const double a = std::abs(r);
    if (a <= k) return {0.5 * r * r, 1.0};
    return {k * a - 0.5 * k * k, k / a};
}

// Geman-McClure with scale c: bounded influence, so gross outliers stop mattering.
inline Robust geman_mcclure(double r, double c) {
    const double c2 = c * c, d = c2 + r * r;
    return {0.5 * c2 * r * r / d, (c2 / d) * (c2 / d)};
}

// Weight of the point-to-point part next to point-to-plane: enough to stop sliding along flat
// regions, small enough that the vertex spacing (about 1 cm) does not bias the fit.
constexpr double kTangential = 0.1;

// One correspondence's term: e is the residual (model point - target) already divided by its
// sigma, n the unit normal it is measured along. The cost is Geman-McClure on the normal part plus
// the weak point-to-point part. For Gauss-Newton, with J the Jacobian of e: add (L J)^T (L J) to
// H and J^T m to g. L is the square root of the weight matrix w (n n^T + t^2 I), t = kTangential:
// sqrt(w) (a n n^T + b I) with b = t and (a + b)^2 = 1 + t^2.
struct PointPlaneTerm {
    double cost;
    Eigen::Matrix3d L;
    Eigen::Vector3d m;
};

// derivatives = false fills only the cost.
inline PointPlaneTerm point_plane(const Eigen::Vector3d& e, const Eigen::Vector3d& n, double gm_scale, bool derivatives = true) {
    const double rn = n.dot(e);
    const Robust rb = geman_mcclure(rn, gm_scale);
    const double t2 = kTangential * kTangential;
    PointPlaneTerm out;
    out.cost = rb.cost + t2 * rb.weight * 0.5 * e.squaredNorm();
    if (!derivatives) return out;
    const double b = kTangential, a = std::sqrt(1 + t2) - b;
    out.L = std::sqrt(rb.weight) * (a * n * n.transpose() + b * Eigen::Matrix3d::Identity());
    out.m = rb.weight * (rn * n + t2 * e);
    return out;
}

// Correspondences kept after trimming a list sorted by distance: the farthest 2 % are dropped
// whatever the loss says (clutter); more would cut off the hands, whose correspondences start
// farthest, and leave them misplaced.
inline std::size_t kept_after_trimming(std::size_t count) { return count - count / 50; }

// Appends to `out` the items of (squared distance, item) pairs that trimming keeps, in their
// order in `found`: those nearer than the cut, then as many at the cut as fit, first come first.
// A selection, not a sort (trimming drops only 2 %): linear time. scratch: reused buffer.
template <class T>
void append_trimmed(const std::vector<std::pair<double, T>>& found, std::vector<double>& scratch, std::vector<T>& out) {
    const std::size_t kept = kept_after_trimming(found.size());
    if (kept == 0) return;
    scratch.resize(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) scratch[i] = found[i].first;
    std::nth_element(scratch.begin(), scratch.begin() + std::ptrdiff_t(kept - 1), scratch.end());
    const double cut = scratch[kept - 1];
    std::size_t below = 0;
    for (const auto& f : found) below += f.first < cut;
    std::size_t at_cut = kept - below;
    for (const auto& f : found)
        if (f.first < cut || (f.first == cut && at_cut > 0 && at_cut--)) out.push_back(f.second);
}

}  // namespace ssc::fitting
