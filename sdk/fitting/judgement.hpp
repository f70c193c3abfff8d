// Whether a fit found the person: the judgement the solver restarts on and the report carries.
//
// What a person can do is the anatomical range of motion (anatomy/joint_limits.hpp), not a distance
// from the rest pose: kneeling, a deep squat, arms overhead are all plausible and fit well. A fit is
// judged wrong only for what is really wrong (docs/fitting.md, "Judging a fit"):
//   joint past its range   a joint further past its anatomical range than the range's measurement
//                          tolerance (a body forced onto data of the other way round);
//   scan unexplained       more of the scan than a scanner's stray surfaces lies far from the fitted
//                          surface (a limb or the trunk where the scan is not);
//   limb on no scan        in a scan taken all round, most of an arm, a leg or the head lies inside the
//                          scan's extent where the scan has no surface (a limb placed behind the back
//                          while the scan shows it in front). Parts outside the scan's extent are
//                          unscanned (a partial scan), not wrong: they are reported, not failed.
//   limb through the body  a forearm or lower leg deep inside the trunk, the head or another limb
//                          (interpenetration.hpp): where the scan shows arms held in front of the
//                          body, the trunk's surface explains the scan that the arm's should.
#pragma once

#include "fitting/kinematics.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ssc::fitting {

class FitProblem;

// The parts of the body judged separately (the skin's dominant joint's part and side). The hands
// and feet are not judged (None): a hand closed otherwise than the scan's puts fingers in front of
// the scanned palm (on simulated scans, 14 % of an arm and hand judged in empty space), and a
// misplaced limb shows in its arm or leg.
enum class BodyRegion : uint8_t { Head = 0, Trunk, LeftArm, RightArm, LeftLeg, RightLeg, None = 255 };
constexpr std::size_t kBodyRegionCount = 6;
// The regions and, after them, the two hands (left, right): vertex_parts().
constexpr std::size_t kBodyPartCount = kBodyRegionCount + 2;
const char* region_name(BodyRegion region);  // "head", "trunk", "left arm", ...

// What is wrong with a fit, the first that applies in this order (None: nothing).
enum class FitProblemKind : uint8_t { None = 0, JointPastRange = 1, ScanUnexplained = 2, LimbOffScan = 3, LimbInside = 4, ArmOffPoints = 5, HandOffPoints = 6 };

// Tolerances of the judgement (see judgement.cpp for the measurements behind them).
// A joint may lie this far past its range (radians) before the fit is judged wrong: the ranges are
// clinical averages measured to about 10 degrees, people differ by as much, and the fit's limit
// walls are soft.
constexpr double kJointRangeTolerance = 0.35;
// Scan shares (see FitReport::unexplained): above the first a fit is redone from other starts,
// above the second it has certainly not found the person.
constexpr double kRetryUnexplained = 0.005;
constexpr double kFailedUnexplained = 0.10;
// A region with more than this share of its surface samples in space the scan saw empty (in front
// of the scan's surface, see judgement.cpp) lies where the scan is not.
constexpr double kOffScanShare = 0.10;
// ... and when more than this share of the scan lies over 2.5 cm from the fitted surface: a part
// missing from a scan (a hole) leaves the rest explained, a misplaced one does not. Of 20 simulated
// scans with 20 % holes, two good fits had an arm 14 and 24 % on empty space (in a hole) with 0 and
// 0.1 % of the scan loosely explained; the two misplaced arms it catches on the pose library, 0.6
// and 0.9 % (docs/fitting.md, "Judging a fit").
constexpr double kLooseShare = 0.003;
// A fit judged right that leaves more than this share of the scan over 2.5 cm from its surface is
// redone from the other start candidates all the same (restart_if_implausible in solver.cpp) and
// kept unless a restart judged right explains the scan better and leaves less of it loose. It
// never fails a fit (clothes or props may leave a real scan loose). On the pose library
// (4 trials) every success left at most 1.2 %, two silent failures 2.3 and 2.6 % (docs/fitting.md).
constexpr double kRetryLoose = 0.02;
// A finished fit judged right that leaves more than kRetryTight of the scan farther than
// kTightDistance from its surface (along the nearest vertex's normal; no vertex within kTightCap
// counts as farther: FitProblem::share_beyond_plane) is tried again (restart_if_off_closely in
// solver.cpp), never failed for it. A hand or forearm placed wrong as a whole lies within the
// distances above; on the pose library (MakeHuman people, 4 trials) every success left at most
// 1.71 % of its scan beyond 8 mm, four of the nine silent failures 2.2-2.7 % (docs/fitting.md).
constexpr double kTightDistance = 0.008;
constexpr double kTightCap = 0.05;
constexpr double kRetryTight = 0.018;
// A finished fit's arm lies off its own points (placed wrong as a whole: elbow up where the
// scan's is down, turned over about its own line) when, of the scan points nearest its upper arm
// and forearm, over kArmOffShare lie beyond kTightDistance from the fit (along the nearest
// vertex's normal), over kArmOffRatio times the trunk's share, and over kArmOffBothSides of those
// on the side fewer of them lie. Clothes and hair leave points off on one side (a bump: 0 % on the
// other; one of ten simulated bumps covered 23 % of an arm's points), and every region alike.
// Pose library (MakeHuman people, 4 trials): successes' arms at most 1.8 %; wrong arms 5-65 %,
// 10-49 % on the lesser side (docs/fitting.md, "Judging a fit").
constexpr double kArmOffShare = 0.05;
constexpr double kArmOffRatio = 3.0;
constexpr double kArmOffBothSides = 0.05;
// A finished fit's hand lies off its own points (turned about the wrist or the forearm, laid on
// the body in another place) when, of the scan points nearest it (at least kHandMinPoints), over
// kHandOffShare lie beyond kTightDistance from the fit, over kArmOffRatio times the trunk's
// share, and over kHandOffSurface of the hand's own surface samples have no scan point within
// 2.5 cm; judged in scans taken all round only (J.all_round). A hand differs from the model's more than an arm does (fingers, closure), so its share
// is set well above the good fits'; no side test: a hand's points lie around thin fingers. The
// surface test tells a bump from a turn: in ten simulated bumpy scans bumps over a hand left 28
// and 41 % of its points beyond 8 mm, but at most 0.9 % of its surface away from the scan; hands
// turned a quarter turn 27-60 %. Pose library (MakeHuman people, 4 trials): successes' hands at
// most 20 % of their points; the hands of silent failures, turned 19-113 degrees, 29-52 %, one
// of them raised over the head with 42 points nearest it (docs/fitting.md, "Judging a fit").
constexpr double kHandOffShare = 0.25;
constexpr double kHandMinPoints = 30;
constexpr double kHandOffSurface = 0.10;
// A forearm or lower leg with more than this share inside another part of the body
// (interpenetration.hpp) passes through it (see judgement.cpp for the measurements).
constexpr double kLimbInsideShare = 0.2;
// A region with at least this share of its samples outside the scan's extent is unscanned.
constexpr double kUnscannedShare = 0.5;
// The trunk's share of surface samples near the scan from which a scan counts as taken all round
// (one depth camera sees about half).
constexpr double kAllRoundCoverage = 0.75;

struct Judgement {
    FitProblemKind problem = FitProblemKind::None;
    // The worst joint's excess past its range (radians) and the joint (-1: none past).
    double joint_excess = 0;
    int32_t joint = -1;
    double unexplained = 0;  // FitProblem::unexplained_share
    double loose = 0;        // the share farther than kLooseDistance from the fitted surface
    // Per region: the share of its surface samples inside the scan's extent with no scan point
    // near, and the share outside the extent (unscanned).
    std::array<double, kBodyRegionCount> off_scan{}, unscanned{};
    double coverage = 0;  // the trunk's share of samples near the scan
    bool all_round = false;
    // The forearm or lower leg most inside another part: its region, that part, and the share.
    int32_t inside_limb = -1, inside_part = -1;
    double inside = 0;
    // Finished fits (judge(..., true)), per region: the share of the scan points nearest it beyond
    // kTightDistance, and of those the share on the side fewer of them lie.
    std::array<double, kBodyRegionCount> off_points{}, off_points_balance{};
    // Finished fits judged with their hands, per hand (0 left, 1 right): the same share for the
    // scan points nearest it.
    std::array<double, 2> hand_off_points{};
    // ... and the share of its surface samples with no scan point within 2.5 cm.
    std::array<double, 2> hand_off_surface{};
    int32_t hand = -1;  // the hand off its points (HandOffPoints), else -1
    int32_t region = -1;  // the region off the scan (LimbOffScan), off its points (ArmOffPoints), the arm of the hand off its
                          // points (HandOffPoints), through the body (LimbInside), else the most unscanned one or -1

    bool acceptable() const { return problem == FitProblemKind::None; }
    // One line: what is wrong, where, by how much ("the left elbow lies 31 degrees past its range").
    std::string describe(const Model& model) const;
    // One line on parts the scan does not show (a partial scan), or empty.
    std::string unscanned_parts() const;
};

// Judges frame f's current state (its kinematics are updated here). Frames without points are
// judged on their joints alone. finished: the fit as it will be returned, also judged for an arm
// off its points (ArmOffPoints); before its last stages (the segments, the wrist search, the
// tight retry) a good fit's arm may still lie that far off (three of the library's successes
// were restarted for it and failed). hands (with finished): also judged for a hand off its
// points (HandOffPoints), for fits whose wrists and hands the fitter searched (a single frame
// from its own start): a capture's tracked frames carry their hands over from the frame before,
// and judging them there failed good frames whose refits went wrong (docs/fitting.md).
Judgement judge(FitProblem& problem, uint32_t f, bool finished = false, bool hands = false);

// Each model vertex's region (by its largest skinning weight's joint).
std::vector<uint8_t> vertex_regions(const LinearModel& lin);
// The same with each hand a part of its own: kBodyRegionCount for the left, + 1 for the right.
std::vector<uint8_t> vertex_parts(const LinearModel& lin);

}  // namespace ssc::fitting
