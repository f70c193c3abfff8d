#include "fitting/judgement.hpp"

#include "anatomy/joint_limits.hpp"
#include "fitting/fit_problem.hpp"
#include "fitting/interpenetration.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ssc::fitting {

namespace {

// A surface sample with a scan point within this distance is on the scan. Booth scans leave the
// armpits, the crotch, the soles and the top of the head unseen, but rarely more than a few
// centimetres from a seen point.
constexpr double kNearScan = 0.04;
// A surface sample off the scan counts as in empty space when it lies this far in front of its
// nearest scan point (along that point's normal), looked for within kFreeSpaceReach.
constexpr double kInFront = 0.02;
constexpr double kFreeSpaceReach = 0.25;
// Scan points farther than this from every fitted vertex are loosely explained (Judgement::loose).
constexpr double kLooseDistance = 0.025;
// The scan's extent: its bounding box grown by this much (metres).
constexpr double kExtentMargin = 0.03;
// Regions with fewer surface samples than this are not judged for lying off the scan.
constexpr std::size_t kMinRegionSamples = 20;

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

BodyRegion region_of(const anatomy::JointRole& role) {
    using anatomy::BodyPart;
    using anatomy::Side;
    switch (role.part) {
    case BodyPart::Head: return BodyRegion::Head;
    case BodyPart::Arm:
        if (role.side == Side::Left) return BodyRegion::LeftArm;
        if (role.side == Side::Right) return BodyRegion::RightArm;
        return BodyRegion::Trunk;
    case BodyPart::Hand:
    case BodyPart::Foot: return BodyRegion::None;
    case BodyPart::Leg:
        if (role.side == Side::Left) return BodyRegion::LeftLeg;
        if (role.side == Side::Right) return BodyRegion::RightLeg;
        return BodyRegion::Trunk;
    case BodyPart::Torso: break;
    }
    return BodyRegion::Trunk;
}

}  // namespace

const char* region_name(BodyRegion region) {
    static const char* const kNames[kBodyRegionCount] = {"head", "trunk", "left arm", "right arm", "left leg", "right leg"};
    return kNames[std::size_t(region)];
}

std::vector<uint8_t> vertex_regions(const LinearModel& lin) {
    std::vector<uint8_t> regions(lin.V, uint8_t(BodyRegion::Trunk));
    for (uint32_t v = 0; v < lin.V; ++v) {
        const uint32_t j = dominant_joint(lin.model.data(), v);
        if (j < lin.roles.size()) regions[v] = uint8_t(region_of(lin.roles[j]));
    }
    return regions;
}

std::vector<uint8_t> vertex_parts(const LinearModel& lin) {
    std::vector<uint8_t> parts = vertex_regions(lin);
    for (uint32_t v = 0; v < lin.V; ++v) {
        const uint32_t j = dominant_joint(lin.model.data(), v);
        if (j >= lin.roles.size() || lin.roles[j].part != anatomy::BodyPart::Hand || lin.roles[j].side == anatomy::Side::Centre) continue;
        parts[v] = uint8_t(kBodyRegionCount + (lin.roles[j].side == anatomy::Side::Left ? 0 : 1));
    }
    return parts;
}

Judgement judge(FitProblem& p, uint32_t f, bool finished, bool hands) {
    Judgement J;
    const LinearModel& lin = p.linear();
    const FitState& state = p.states()[f];
    // Joints past their ranges.
    for (uint32_t j = 1; j < lin.J && j < lin.limits.size(); ++j) {
        const anatomy::JointLimit& lim = lin.limits[j];
        if (!lim.limited) continue;
        const Vector3d c = anatomy::anatomical_angles(lim, state.pose[j]);
        for (int a = 0; a < 3; ++a) {
            const double excess = std::max(c[a] - lim.hi[a], lim.lo[a] - c[a]);
            if (excess > J.joint_excess) J.joint_excess = excess, J.joint = int32_t(j);
        }
    }
    if (p.has_points(f)) {
        J.unexplained = p.unexplained_share(f);
        J.loose = p.share_beyond(f, kLooseDistance);
        const FrameData& fd = p.frame(f);
        Vector3d lo = fd.points.front(), hi = lo;
        for (const Vector3d& q : fd.points) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
        lo.array() -= kExtentMargin, hi.array() += kExtentMargin;
        const std::vector<Vector3d>& posed = p.posed_sample(f);
        const std::vector<uint8_t>& regions = p.sample_regions();
        std::array<std::size_t, kBodyRegionCount> total{}, off{}, outside{}, near{};
        for (std::size_t s = 0; s < posed.size(); ++s) {
            const std::size_t r = regions[s];
            if (r >= kBodyRegionCount) continue;
            ++total[r];
            const Vector3d& x = posed[s];
            if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) {
                ++outside[r];
                continue;
            }
            if (fd.scan_grid.nearest(x, kNearScan, nullptr) != GridIndex::kNone) {
                ++near[r];
                continue;
            }
            // Off the scan: wrong only where the scan saw empty space, in front of its nearest
            // surface (scanners see a surface from the side its normal faces); behind it the part
            // may be hidden (an arm behind the back in a front view, the underside of a lying body).
            if (!fd.oriented) continue;
            const uint32_t q = fd.scan_grid.nearest(x, kFreeSpaceReach, nullptr);
            if (q != GridIndex::kNone && (x - fd.points[q]).dot(fd.normals[q]) > kInFront) ++off[r];
        }
        const std::size_t trunk = std::size_t(BodyRegion::Trunk);
        J.coverage = total[trunk] ? double(near[trunk]) / double(total[trunk]) : 0;
        J.all_round = J.coverage >= kAllRoundCoverage;
        double most_unscanned = 0;
        for (std::size_t r = 0; r < kBodyRegionCount; ++r) {
            if (total[r] == 0) continue;
            J.off_scan[r] = double(off[r]) / double(total[r]);
            J.unscanned[r] = double(outside[r]) / double(total[r]);
            if (J.unscanned[r] > most_unscanned) most_unscanned = J.unscanned[r], J.region = int32_t(r);
        }
        if (most_unscanned < kUnscannedShare) J.region = -1;
        double worst = kOffScanShare;
        for (std::size_t r = 0; r < kBodyRegionCount; ++r)
            if (total[r] >= kMinRegionSamples && J.off_scan[r] > worst) worst = J.off_scan[r], J.region = int32_t(r);
        // A part missing from a scan (a hole) leaves the rest of the scan explained; a part placed
        // where the scan saw nothing has left its own points loosely explained elsewhere.
        if (worst > kOffScanShare && J.loose > kLooseShare) J.problem = FitProblemKind::LimbOffScan;
        if (finished) {
            // One pass over the scan for the regions and the hands (kBodyPartCount parts).
            std::array<double, kBodyPartCount> share{}, balance{}, points{};
            p.region_sides_beyond_plane(f, kTightDistance, kTightCap, p.vertex_parts(), share.data(), balance.data(), kBodyPartCount, points.data());
            std::copy_n(share.begin(), kBodyRegionCount, J.off_points.begin());
            std::copy_n(balance.begin(), kBodyRegionCount, J.off_points_balance.begin());
            const std::size_t left = std::size_t(BodyRegion::LeftArm), right = std::size_t(BodyRegion::RightArm);
            for (const std::size_t arm : {left, right})
                if (J.problem == FitProblemKind::None && J.off_points[arm] > kArmOffShare && J.off_points[arm] > kArmOffRatio * J.off_points[trunk] &&
                    J.off_points_balance[arm] > kArmOffBothSides)
                    J.problem = FitProblemKind::ArmOffPoints, J.region = int32_t(arm);
            // Hands (when asked for) only in scans taken all round: one view sees one side of a
            // hand, and its back lies off the scan however the hand is turned.
            if (hands && J.all_round) {
                // The hand's own surface off the scan: a bump (clothes, a watch) lies over a hand
                // whose surface stays under it; a hand turned sticks out of its points.
                const std::vector<uint8_t>& part_of = p.vertex_parts();
                const std::vector<uint32_t>& sample = p.vertex_sample();
                std::array<double, 2> samples{}, away{};
                for (std::size_t s = 0; s < posed.size(); ++s) {
                    const std::size_t h = std::size_t(part_of[sample[s]]) - kBodyRegionCount;  // wraps for the regions
                    if (h > 1) continue;
                    samples[h] += 1;
                    away[h] += fd.scan_grid.nearest(posed[s], kLooseDistance, nullptr) == GridIndex::kNone;
                }
                for (std::size_t h = 0; h < 2; ++h) {
                    J.hand_off_points[h] = share[kBodyRegionCount + h];
                    J.hand_off_surface[h] = samples[h] > 0 ? away[h] / samples[h] : 0.0;
                    if (J.problem == FitProblemKind::None && points[kBodyRegionCount + h] >= kHandMinPoints && J.hand_off_points[h] > kHandOffShare &&
                        J.hand_off_points[h] > kArmOffRatio * J.off_points[trunk] && J.hand_off_surface[h] > kHandOffSurface)
                        J.problem = FitProblemKind::HandOffPoints, J.hand = int32_t(h),
                        J.region = int32_t(h == 0 ? BodyRegion::LeftArm : BodyRegion::RightArm);
                }
            }
        }
    }
    // A limb through the body, with or without a scan. The least of the problems: any other says
    // more about where the fit went wrong.
    const LimbsInside inside = p.limbs_inside(f);
    J.inside = inside.worst, J.inside_limb = inside.limb, J.inside_part = inside.part;
    if (J.inside > kLimbInsideShare && J.problem == FitProblemKind::None) J.problem = FitProblemKind::LimbInside, J.region = J.inside_limb;
    if (J.unexplained > kRetryUnexplained) J.problem = FitProblemKind::ScanUnexplained;  // 0 without points
    if (J.joint_excess > kJointRangeTolerance) J.problem = FitProblemKind::JointPastRange;
    return J;
}

std::string Judgement::describe(const Model& model) const {
    std::ostringstream s;
    s.precision(0);
    s << std::fixed;
    switch (problem) {
    case FitProblemKind::None: return "";
    case FitProblemKind::JointPastRange:
        s << "joint " << model.data().skeleton.joint_names[std::size_t(joint)] << " lies " << joint_excess * kDegrees
          << " degrees past its anatomical range";
        break;
    case FitProblemKind::ScanUnexplained:
        s << unexplained * 100 << " % of the scan lies more than 5 cm from the fitted surface";
        // A tenth of the scan is more than any limb: the whole body is wrong, or the scan holds
        // more than a person (test_fit_bad_scans.cpp: two people 70 %, a box held 17 %, a crate 46 %).
        if (unexplained >= kFailedUnexplained)
            s << " (the body in the wrong place, or more than one person in the scan: another person, an object held, a floor or "
                 "a wall; crop the scan to the person)";
        else
            s << " (a limb or the trunk where the scan is not)";
        break;
    case FitProblemKind::LimbInside:
        s << "the " << region_name(BodyRegion(inside_limb)) << " passes through the " << region_name(BodyRegion(inside_part)) << " ("
          << inside * 100 << " % of its " << (inside_limb >= int32_t(BodyRegion::LeftLeg) ? "lower leg" : "forearm") << " inside)";
        break;
    case FitProblemKind::ArmOffPoints:
        s << "the " << region_name(BodyRegion(region)) << " lies off its points, placed wrong as a whole (" << off_points[std::size_t(region)] * 100
          << " % of the scan nearest it over " << kTightDistance * 1000 << " mm from the fitted surface, on both sides of it)";
        break;
    case FitProblemKind::HandOffPoints:
        s << "the " << (hand == 0 ? "left" : "right") << " hand lies off its points, turned or placed wrong (" << hand_off_points[std::size_t(hand)] * 100
          << " % of the scan nearest it over " << kTightDistance * 1000 << " mm from the fitted surface)";
        break;
    case FitProblemKind::LimbOffScan:
        s << "the " << region_name(BodyRegion(region)) << " lies where the scan saw empty space (" << off_scan[std::size_t(region)] * 100
          << " % of it)";
        break;
    }
    return s.str();
}

std::string Judgement::unscanned_parts() const {
    std::string parts;
    for (std::size_t r = 0; r < kBodyRegionCount; ++r)
        if (unscanned[r] >= kUnscannedShare) parts += std::string(parts.empty() ? "" : ", ") + region_name(BodyRegion(r));
    return parts.empty() ? parts : "the scan does not show the " + parts + " (outside its extent): fitted from the shape alone";
}

}  // namespace ssc::fitting
