#include "fitting/head_search.hpp"

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

// Caps of the measure (metres): scan points up to 5 cm, the head's own vertices up to 2 cm (a
// head's back or crown often lies in a scan's hole).
constexpr double kCap = 0.05, kModelCap = 0.02;
// A turn must lower the measure by this fraction to replace the fit's head (and have the fine
// stage run again). Library of poses, MakeHuman people, 2 trials: the heads turned 20 to 40
// degrees wrong gained 6.5 to 26 %, most good fits' heads 0.3 to 2 %; with 0.3 % three in four
// fits ran the fine stage again (a fifth more CPU time) for a few tenths of a millimetre, and
// small turns settled by the polish alone made lying fits 1 to 4 mm worse. The solver now keeps a
// turn only when the fit then lies closer to the scan (keep_if_closer in solver.cpp), which
// let the gain come down to 2 %: 4 trials of the library, 71 -> 74 % success, silent failures 9 -> 8.
constexpr double kMinGain = 0.02;
// Scan and model points scored (a prefix of the frame's random samples). Half of the 3000, with
// two grid turns refined instead of three: 16 ms a search instead of 48, the same fits of the
// pose library.
constexpr std::size_t kSamples = 1500;

}  // namespace

bool search_head(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                 ThreadPool& pool) {
    const std::vector<anatomy::JointLimit>& limits = kin.linear().limits;
    const std::vector<anatomy::JointRole>& roles = kin.linear().roles;
    std::vector<std::size_t> head;  // the head part's joints, parents first: the neck, the head
    for (std::size_t j = 0; j < roles.size() && head.size() < 2; ++j)
        if (roles[j].part == anatomy::BodyPart::Head && limits[j].limited) head.push_back(j);
    if (head.size() < 2) return false;
    const std::size_t jn = head[0], jh = head[1];
    const anatomy::JointLimit &ln = limits[jn], &lh = limits[jh];
    std::vector<Vector3d> posed, posed_normals;
    kin.update(state, false);
    posed_surface(body, state, posed, &posed_normals);
    struct Worker {
        FitState state;
        Kinematics kin;
        LimbScore score;
    };
    const LimbScore head_score(kin, cloud, vertex_sample, posed, posed_normals, uint32_t(jn), kCap, kModelCap, std::min<std::size_t>(vertex_sample.size(), kSamples));
    std::vector<Worker> workers(pool.size(), Worker{state, kin, head_score});
    using Angles = std::array<double, 6>;  // the neck's three anatomical angles, then the head's
    auto score = [&](unsigned w, const Angles& a, double bound) {
        Worker& k = workers[w];
        k.state.pose[jn] = anatomy::rotation_from_angles(ln, Vector3d(a[0], a[1], a[2]));
        k.state.pose[jh] = anatomy::rotation_from_angles(lh, Vector3d(a[3], a[4], a[5]));
        k.kin.update(k.state, false);
        return k.score(k.kin, bound);
    };
    const Vector3d n0 = anatomy::anatomical_angles(ln, state.pose[jn]), h0 = anatomy::anatomical_angles(lh, state.pose[jh]);
    const Angles start{n0[0], n0[1], n0[2], h0[0], h0[1], h0[2]};
    const double current = score(0, start, std::numeric_limits<double>::infinity());
    // The grid: the turn shared by the neck and the head in proportion to their ranges (a head
    // turned 45 degrees is past the neck's range alone), five turns about the neck's axis (where
    // a round head is most ambiguous) by three tilts each way.
    std::vector<AngleCandidate<6>> grid{{start, current}};
    for (double f : {0.0, -0.6, 0.6})
        for (double r : {0.0, -0.8, -0.4, 0.4, 0.8})
            for (double l : {0.0, -0.6, 0.6}) {
                Angles a{};
                const double t[3] = {f, r, l};
                for (int c = 0; c < 3; ++c) {
                    a[std::size_t(c)] = 0.5 * (ln.lo[c] + ln.hi[c]) + t[c] * 0.5 * (ln.hi[c] - ln.lo[c]);
                    a[std::size_t(c) + 3] = 0.5 * (lh.lo[c] + lh.hi[c]) + t[c] * 0.5 * (lh.hi[c] - lh.lo[c]);
                }
                grid.push_back({a, 0});
            }
    // Then a pattern search over the six angles within their ranges.
    Angles lo{}, hi{};
    for (std::size_t c = 0; c < 6; ++c) lo[c] = (c < 3 ? ln : lh).lo[c % 3], hi[c] = (c < 3 ? ln : lh).hi[c % 3];
    const AngleCandidate<6> best = search_angles(std::move(grid), lo, hi, pool, score);
    if (current - best.score < kMinGain * current) {
        kin.update(state, false);
        return false;
    }
    state.pose[jn] = anatomy::rotation_from_angles(ln, Vector3d(best.a[0], best.a[1], best.a[2]));
    state.pose[jh] = anatomy::rotation_from_angles(lh, Vector3d(best.a[3], best.a[4], best.a[5]));
    kin.update(state, false);
    return true;
}

}  // namespace ssc::fitting
