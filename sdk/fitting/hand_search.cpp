#include "fitting/hand_search.hpp"

#include "anatomy/hand_closure.hpp"
#include "fitting/posed_surface.hpp"

#include <limits>
#include <string>

namespace ssc::fitting {

namespace {

constexpr double kClosures[] = {0.0, 0.25, 0.5, 0.75, 1.0};
// Caps of the measure (metres): a finger in the wrong place is off by 1 to 8 cm. Model vertices
// count up to 2 cm: open fingers lying in a scan's hole otherwise pay enough to close a hand that
// is open (benchmark before kMinGain, 30 scans of open hands: 2.47 mm mean error with 3 cm, 2.14
// with 2 cm, 2.08 without the search; closed hands, 10 scans: 4.0, 5.5 and 24.4 mm on the hands).
constexpr double kCap = 0.05, kModelCap = 0.02;
// A closure must lower the measure by this fraction to replace the current fingers. On scans of
// open hands the false closures gained 0.01 to 0.14 %, on scans of closed hands the closures found
// mostly 0.2 to 2.5 %. Benchmark (hands scenario 30 scans; 100 frames of open hands), hands' error
// and frames' mean error: 0.2 % 6.4 and 2.05 mm, 0.3 % 8.3 and 1.97, 0.4 % 10.0 and 1.95; without
// the search 23.7 and 1.93.
constexpr double kMinGain = 0.003;

}  // namespace

void set_hand_closure(const Model& model, FitState& s, int hand, double closure) {
    const auto rotations = anatomy::hand_closure(model, hand == 0 ? 'l' : 'r', closure);
    if (rotations.empty()) return;
    for (const auto& r : rotations) s.pose[r.joint] = r.rotation;
    s.hand_closure[hand] = closure;
}

void search_hands(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample) {
    const Model& model = kin.model();
    std::vector<Vector3d> posed, posed_normals;
    for (int hand = 0; hand < 2; ++hand) {
        const int64_t joint = model.find_joint(hand == 0 ? "hand_l" : "hand_r");
        if (joint < 0 || anatomy::hand_closure(model, hand == 0 ? 'l' : 'r', 1.0).empty()) continue;
        kin.update(state, false);
        posed_surface(body, state, posed, &posed_normals);
        LimbScore score(kin, cloud, vertex_sample, posed, posed_normals, uint32_t(joint), kCap, kModelCap, vertex_sample.size());
        double best = score(kin);  // the current fingers: kept unless a closure gains kMinGain
        const double current = best;
        FitState trial = state, chosen = state;
        auto consider = [&](double c) {
            if (c < 0 || c > 1) return;
            set_hand_closure(model, trial, hand, c);
            kin.update(trial, false);
            const double s = score(kin, best);
            if (s < best) best = s, chosen = trial;
        };
        for (const double c : kClosures) consider(c);
        // Then halfway to the grid's neighbours of the best.
        const double coarse = chosen.hand_closure[hand];
        for (const double c : {coarse - 0.125, coarse + 0.125}) consider(c);
        if (current - best >= kMinGain * current) state = chosen;
    }
    kin.update(state, false);
}

}  // namespace ssc::fitting
