#include "fitting/wrist_search.hpp"

#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"
#include "fitting/angle_search.hpp"
#include "fitting/posed_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ssc::fitting {

namespace {

// Caps of the measure (metres), the head search's: scan points up to 5 cm, the forearm's and
// hand's own vertices up to 2 cm (fingers often lie in a scan's holes).
constexpr double kCap = 0.05, kModelCap = 0.02;
// A pose must lower the measure by this fraction to replace the fit's. Library of poses,
// MakeHuman people, 4 trials, each kept only when the fit then lies closer to the scan: at 5 %
// no fit ended worse; at 3 % and 2 % hands behind the head went from 8.3 to 14.6 mm.
constexpr double kMinGain = 0.05;
constexpr std::size_t kSamples = 1500;

}  // namespace

uint32_t wrist_on(const LinearModel& lin, std::size_t elbow) {
    for (uint32_t j = 0; j < lin.J; ++j)
        if (lin.roles[j].part == anatomy::BodyPart::Hand && lin.chains[j].size() > 1 && lin.chains[j][1] == elbow) return j;
    return lin.J;
}

bool search_wrists(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                   ThreadPool& pool) {
    const LinearModel& lin = kin.linear();
    const std::vector<anatomy::JointLimit>& limits = lin.limits;
    const std::vector<anatomy::JointRole>& roles = lin.roles;
    bool moved = false;
    for (const anatomy::Side side : {anatomy::Side::Left, anatomy::Side::Right}) {
        const int64_t elbow = anatomy::find_limb_joint(roles, anatomy::BodyPart::Arm, side, anatomy::LimbJoint::Middle);
        if (elbow < 0) continue;
        const std::size_t je = std::size_t(elbow);
        const std::size_t jw = wrist_on(lin, je);
        if (jw == lin.J || !limits[je].limited || !limits[jw].limited) continue;
        const anatomy::JointLimit &le = limits[je], &lw = limits[jw];
        kin.update(state, false);
        std::vector<Vector3d> posed, posed_normals;
        posed_surface(body, state, posed, &posed_normals);
        struct Worker {
            FitState state;
            Kinematics kin;
            LimbScore score;
        };
        const LimbScore arm_score(kin, cloud, vertex_sample, posed, posed_normals, uint32_t(je), kCap, kModelCap,
                                  std::min<std::size_t>(vertex_sample.size(), kSamples));
        std::vector<Worker> workers(pool.size(), Worker{state, kin, arm_score});
        const Vector3d e0 = anatomy::anatomical_angles(le, state.pose[je]), w0 = anatomy::anatomical_angles(lw, state.pose[jw]);
        // The forearm's turn (the elbow's axial angle), then the wrist's three angles; the elbow's
        // bend and sideways angle stay the fit's.
        using Angles = std::array<double, 4>;
        auto score = [&](unsigned w, const Angles& a, double bound) {
            Worker& k = workers[w];
            k.state.pose[je] = anatomy::rotation_from_angles(le, Vector3d(e0[0], a[0], e0[2]));
            k.state.pose[jw] = anatomy::rotation_from_angles(lw, Vector3d(a[1], a[2], a[3]));
            k.kin.update(k.state, false);
            return k.score(k.kin, bound);
        };
        const Angles start{e0[1], w0[0], w0[1], w0[2]};
        const double current = score(0, start, std::numeric_limits<double>::infinity());
        std::vector<AngleCandidate<4>> grid{{start, current}};
        const double mid_w = 0.5 * (lw.lo[0] + lw.hi[0]), half_w = 0.5 * (lw.hi[0] - lw.lo[0]);
        for (double t : {-1.0, -2.0 / 3, -1.0 / 3, 0.0, 1.0 / 3, 2.0 / 3, 1.0})
            for (double b : {0.0, -0.5, 0.5})
                grid.push_back({{0.5 * (le.lo[1] + le.hi[1]) + t * 0.5 * (le.hi[1] - le.lo[1]), mid_w + b * half_w, 0.5 * (lw.lo[1] + lw.hi[1]),
                                 0.5 * (lw.lo[2] + lw.hi[2])},
                                0});
        // Then a pattern search over the forearm's turn and the wrist's three angles.
        const Angles lo{le.lo[1], lw.lo[0], lw.lo[1], lw.lo[2]}, hi{le.hi[1], lw.hi[0], lw.hi[1], lw.hi[2]};
        const AngleCandidate<4> best = search_angles(std::move(grid), lo, hi, pool, score);
        if (current - best.score < kMinGain * current) continue;
        state.pose[je] = anatomy::rotation_from_angles(le, Vector3d(e0[0], best.a[0], e0[2]));
        state.pose[jw] = anatomy::rotation_from_angles(lw, Vector3d(best.a[1], best.a[2], best.a[3]));
        moved = true;
    }
    kin.update(state, false);
    return moved;
}

bool turn_arm_over(Kinematics& kin, FitState& state, anatomy::Side side) {
    const LinearModel& lin = kin.linear();
    const int64_t upper = anatomy::find_limb_joint(lin.roles, anatomy::BodyPart::Arm, side, anatomy::LimbJoint::Upper);
    const int64_t elbow = anatomy::find_limb_joint(lin.roles, anatomy::BodyPart::Arm, side, anatomy::LimbJoint::Middle);
    if (upper < 0 || elbow < 0) return false;
    const uint32_t wrist = wrist_on(lin, std::size_t(elbow));
    if (wrist == lin.J) return false;
    kin.update(state, false);
    const Vector3d line = kin.joint_position(wrist) - kin.joint_position(uint32_t(upper));
    if (line.norm() < 1e-6) return false;
    // A world-frame rotation of the joint's posed rotation about its posed position, as
    // Kinematics::apply makes one: the local pose P <- exp(A^T w) P.
    const Vector3d axis = kin.local_from_world(uint32_t(upper)) * line.normalized();
    Eigen::Quaterniond& pose = state.pose[std::size_t(upper)];
    pose = (Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, axis)) * pose).normalized();
    kin.update(state, false);
    return true;
}

}  // namespace ssc::fitting
