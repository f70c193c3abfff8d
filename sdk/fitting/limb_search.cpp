#include "fitting/limb_search.hpp"

#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"
#include "fitting/explained.hpp"
#include "fitting/posed_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace ssc::fitting {

namespace {

// Scan and model points each candidate is scored on (a prefix of the frame's random samples).
// 300 against 500: the same mean errors on the benchmark (30 trials each), 6 % less CPU time.
constexpr std::size_t kLimbSamples = 300;
// Grid poses scoring worse than this many times the current pose are not refined. When the current
// pose is already right (most limbs) that leaves little to refine. On the benchmark's scans and
// depth images about a tenth of the limbs that moved had won from beyond it (up to 4.3 times),
// each gaining 4 to 17 % of its score, a fine adjustment the fit's later stages also make: without
// them the mean errors stayed the same (30 trials each).
constexpr double kRefineWithin = 1.5;

}  // namespace

LimbGains search_limbs(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                       ThreadPool& pool, std::size_t count) {
    std::vector<Vector3d> posed, posed_normals;
    const std::vector<anatomy::JointLimit>& limits = kin.linear().limits;
    const std::vector<anatomy::JointRole>& roles = kin.linear().roles;
    constexpr double d = M_PI / 180;
    struct Limb {
        anatomy::BodyPart part;
        std::vector<Vector3d> upper_angles, middle_angles;  // radians (flexion, axial, abduction)
    };
    std::vector<Limb> limbs(2);
    limbs[0] = {anatomy::BodyPart::Arm, {}, {}};
    for (double abd : {40.0, 0.0, -47.0, -100.0, -132.0})  // along the body ... overhead
        for (double flex : {0.0, -60.0, -110.0})           // in the frontal plane ... forward
            for (double axial : {0.0, -70.0, 70.0})         // where a bent elbow points
                limbs[0].upper_angles.push_back(d * Vector3d(flex, axial, abd));
    for (double flex : {40.0, -20.0, -80.0}) limbs[0].middle_angles.push_back(d * Vector3d(flex, 0, 0));  // straight ... bent
    limbs[1] = {anatomy::BodyPart::Leg, {}, {}};
    for (double flex : {0.0, -45.0, -90.0})
        for (double abd : {0.0, -25.0}) limbs[1].upper_angles.push_back(d * Vector3d(flex, 0, abd));
    for (double flex : {0.0, 45.0, 90.0, 120.0}) limbs[1].middle_angles.push_back(d * Vector3d(flex, 0, 0));
    LimbGains gains{};
    std::size_t index = 0;  // the limb's place in the search order (kLimbCount in all)
    // A wider cap than the start search's: a candidate limb a few centimetres off its points (the
    // coarse grid) must still score better than one lying on the torso. Model vertices left
    // unexplained cost less (holes; see LimbScore): 8 cm, chosen on the benchmark's scans and the
    // tests (15 cm let an arm raised over a hole curl onto the head instead).
    constexpr double cap = 0.15, model_cap = 0.08;
    for (const Limb& limb : limbs)
        for (const anatomy::Side side : {anatomy::Side::Left, anatomy::Side::Right}) {
            if (index++ >= count) return gains;
            const int64_t ju = anatomy::find_limb_joint(roles, limb.part, side, anatomy::LimbJoint::Upper);
            const int64_t jm = anatomy::find_limb_joint(roles, limb.part, side, anatomy::LimbJoint::Middle);
            if (ju < 0 || jm < 0 || !limits[std::size_t(ju)].limited || !limits[std::size_t(jm)].limited) continue;
            kin.update(state, false);
            posed_surface(body, state, posed, &posed_normals);
            const FitState keep = state;
            const anatomy::JointLimit& lu = limits[std::size_t(ju)];
            const anatomy::JointLimit& lm = limits[std::size_t(jm)];
            // Candidates are scored on the pool's threads, each with its own state,
            // kinematics and scorer; the results do not depend on the thread count.
            struct Worker {
                FitState state;
                Kinematics kin;
                LimbScore score;
            };
            const LimbScore limb_score(kin, cloud, vertex_sample, posed, posed_normals, uint32_t(ju), cap, model_cap, kLimbSamples);
            std::vector<Worker> workers(pool.size(), Worker{keep, kin, limb_score});
            auto score = [&](unsigned w, const Vector3d& au, const Vector3d& am, double bound) {
                Worker& k = workers[w];
                k.state.pose[std::size_t(ju)] = anatomy::rotation_from_angles(lu, au);
                k.state.pose[std::size_t(jm)] = anatomy::rotation_from_angles(lm, am);
                k.kin.update(k.state, false);
                return k.score(k.kin, bound);
            };
            struct Candidate {
                Vector3d upper, middle;
                double score;
            };
            auto by_score = [](const Candidate& x, const Candidate& y) { return x.score < y.score; };
            // Upper and middle joint together: which way a bent elbow points depends on
            // both (an arm raised sideways with the forearm up or forward).
            std::vector<Vector3d> uppers{anatomy::anatomical_angles(lu, keep.pose[std::size_t(ju)])};
            std::vector<Vector3d> middles{anatomy::anatomical_angles(lm, keep.pose[std::size_t(jm)])};
            uppers.insert(uppers.end(), limb.upper_angles.begin(), limb.upper_angles.end());
            middles.insert(middles.end(), limb.middle_angles.begin(), limb.middle_angles.end());
            std::vector<Candidate> grid;
            for (const auto& au : uppers)
                for (const auto& am : middles) grid.push_back({au, am, 0});
            constexpr std::size_t kRefined = 6;
            // Only grid poses scoring within kRefineWithin of the current pose are refined: their
            // scoring stops at that bound, and the others are dropped.
            const double current = score(0, grid[0].upper, grid[0].middle, std::numeric_limits<double>::infinity());
            grid[0].score = current;
            const double bound = kRefineWithin * current;
            pool.parallel_for(grid.size() - 1, [&](std::size_t i, unsigned w) {
                grid[i + 1].score = score(w, grid[i + 1].upper, grid[i + 1].middle, bound);
            });
            grid.erase(std::remove_if(grid.begin() + 1, grid.end(), [&](const Candidate& c) { return c.score >= bound; }), grid.end());
            std::stable_sort(grid.begin(), grid.end(), by_score);
            // The grid is coarse (20 to 60 degrees apart): refine the best few by pattern
            // search over the upper joint's three angles and the middle joint's bend, in
            // 16 degree steps, then the best two in 8 and 4 degree steps.
            // A step only needs to know whether a neighbour beats the current candidate, so its
            // scoring stops at the current score (LimbScore's bound). The search returns to
            // poses it has scored (a step back, the 4 degree steps on the 8 degree lattice):
            // those come from a memo. A bounded score stays valid as the current score only falls.
            struct Scored {
                std::array<int64_t, 4> key;
                double score;
            };
            auto key_of = [](const Candidate& y) {
                // Angles repeat up to rounding (a step there and back): keys in units of 1e-7 rad.
                return std::array<int64_t, 4>{std::llround(y.upper[0] * 1e7), std::llround(y.upper[1] * 1e7),
                                              std::llround(y.upper[2] * 1e7), std::llround(y.middle[0] * 1e7)};
            };
            auto refine = [&](Candidate& x, double step, unsigned w, std::vector<Scored>& memo) {
                for (bool improved = true; improved;) {
                    improved = false;
                    for (int coord = 0; coord < 4; ++coord)
                        for (double sign : {1.0, -1.0}) {
                            Candidate y = x;
                            double& angle = coord < 3 ? y.upper[coord] : y.middle[0];
                            const double lo = coord < 3 ? lu.lo[coord] : lm.lo[0], hi = coord < 3 ? lu.hi[coord] : lm.hi[0];
                            // Within the joint's range: the fit's limits would pull it back.
                            const double moved_to = std::clamp(angle + sign * step, lo, hi);
                            if (moved_to == angle) continue;
                            angle = moved_to;
                            const std::array<int64_t, 4> key = key_of(y);
                            const auto seen = std::find_if(memo.begin(), memo.end(), [&](const Scored& m) { return m.key == key; });
                            if (seen != memo.end()) {
                                y.score = seen->score;
                            } else {
                                y.score = score(w, y.upper, y.middle, x.score);
                                memo.push_back({key, y.score});
                            }
                            if (y.score < x.score) x = y, improved = true;
                        }
                }
            };
            // Each refined candidate keeps its own memo: its refinements only revisit its own poses.
            struct Refined {
                Candidate x;
                std::vector<Scored> memo;
            };
            auto by_refined_score = [](const Refined& a, const Refined& b) { return a.x.score < b.x.score; };
            std::vector<Refined> top;
            for (std::size_t i = 0; i < grid.size() && i < kRefined; ++i) top.push_back({grid[i], {}});
            pool.parallel_for(top.size(), [&](std::size_t i, unsigned w) { refine(top[i].x, 16 * d, w, top[i].memo); });
            std::stable_sort(top.begin(), top.end(), by_refined_score);
            top.resize(std::min<std::size_t>(top.size(), 2));
            pool.parallel_for(top.size(), [&](std::size_t i, unsigned w) {
                refine(top[i].x, 8 * d, w, top[i].memo), refine(top[i].x, 4 * d, w, top[i].memo);
            });
            const Candidate best = std::min_element(top.begin(), top.end(), by_refined_score)->x;
            FitState best_state = keep;
            if (best.score < current) {
                best_state.pose[std::size_t(ju)] = anatomy::rotation_from_angles(lu, best.upper);
                best_state.pose[std::size_t(jm)] = anatomy::rotation_from_angles(lm, best.middle);
                gains[index - 1] = 1 - best.score / current;
            }
            state = best_state;
        }
    return gains;
}

}  // namespace ssc::fitting
