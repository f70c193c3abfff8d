#include "learning/acceptance.hpp"

#include "anatomy/joint_limits.hpp"
#include "fitting/posed_surface.hpp"
#include "synthesis/body.hpp"

#include <cmath>
#include <cstdio>

namespace ssc::learning {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
    char text[200];
    std::snprintf(text, sizeof text, f, a, b, c);
    return text;
}

}  // namespace

Inspection inspect_registration(const Model& model, const scan_files::RegistrationRecord& record, const AcceptanceRules& rules) {
    Inspection out;
    for (const auto& q : record.quality.regions) {
        const auto it = rules.min_within_by_region.find(q.region);
        const double need = it == rules.min_within_by_region.end() ? rules.min_within : it->second;
        if (q.below[3] < need)
            out.reasons.push_back(q.region + fmt(": %.0f%% of vertices within 20 mm of the scan (at least %.0f%%)", 100 * q.below[3], 100 * need));
        const std::size_t all = record.quality.scan_to_registration.count;
        const double unexplained = all ? double(q.scan_to_registration.beyond_20mm) / double(all) : 0;
        if (unexplained > rules.max_unexplained)
            out.reasons.push_back(q.region + fmt(": %.1f%% of the scan's points nearest to it lie over 20 mm from it (at most %.1f%%)", 100 * unexplained,
                                                 100 * rules.max_unexplained));
    }
    const scan_files::RegisteredScan& r = record.registered;
    if (r.has_fit && r.vertices.size() == model.vertex_count()) {
        Body body(model, nullptr);
        std::vector<Eigen::Vector3d> fitted;
        fitting::posed_surface(body, r.fit, fitted);
        const auto& tris = model.data().mesh.triangles;
        const std::size_t T = tris.size() / 3;
        std::size_t folded = 0, stretched = 0;
        for (std::size_t t = 0; t < T; ++t) {
            const uint32_t a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
            const Eigen::Vector3d n0 = (fitted[b] - fitted[a]).cross(fitted[c] - fitted[a]);
            const Eigen::Vector3d n1 = (r.vertices[b] - r.vertices[a]).cross(r.vertices[c] - r.vertices[a]);
            const double a0 = n0.norm(), a1 = n1.norm();
            if (a0 <= 0) continue;  // a degenerate triangle in the fit says nothing
            if (n0.dot(n1) < 0) ++folded;
            else if (a1 > rules.stretch * a0 || a1 * rules.stretch < a0) ++stretched;
        }
        out.folded = double(folded) / double(T);
        out.stretched = double(stretched) / double(T);
        if (out.folded > rules.max_folded)
            out.reasons.push_back(fmt("%.2f%% of triangles folded over (at most %.2f%%)", 100 * out.folded, 100 * rules.max_folded));
        if (out.stretched > rules.max_stretched)
            out.reasons.push_back(fmt("%.2f%% of triangles stretched or squashed over %.0fx (at most %.2f%%)", 100 * out.stretched, rules.stretch,
                                      100 * rules.max_stretched));
        const std::vector<anatomy::JointLimit> limits = anatomy::joint_limits(model);
        for (std::size_t j = 0; j < limits.size() && j < r.fit.pose.size(); ++j) {
            if (!limits[j].limited) continue;
            const Eigen::Vector3d c = anatomy::anatomical_angles(limits[j], r.fit.pose[j].normalized());
            for (int k = 0; k < 3; ++k) {
                const double excess = std::max(limits[j].lo[k] - c[k], c[k] - limits[j].hi[k]);
                if (excess > out.joint_excess) out.joint_excess = excess, out.worst_joint = model.data().skeleton.joint_names[j];
            }
        }
        if (out.joint_excess > rules.joint_margin)
            out.reasons.push_back(out.worst_joint + fmt(" bent %.0f degrees beyond its range of motion (at most %.0f)", out.joint_excess * 180 / M_PI,
                                                        rules.joint_margin * 180 / M_PI));
    }
    out.accepted = out.reasons.empty();
    return out;
}

}  // namespace ssc::learning
