// The shape change that makes one forearm longer or shorter (fitting/forearm_length.hpp), which the
// fitter tries on a hand it closed (solver.cpp: reopen_closed_hands).
#include "fitting/forearm_length.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace ssc;
using Eigen::Vector3d;

namespace {

Vector3d rest_joint(const fitting::LinearModel& lin, const std::vector<double>& shape, uint32_t j) {
    Vector3d x = lin.joint_mean[j];
    for (uint32_t a = 0; a < 3; ++a)
        for (uint32_t k = 0; k < lin.K; ++k) x[a] += lin.joint_basis[(std::size_t(j) * 3 + a) * lin.K + k] * shape[k];
    return x;
}

bool in_hand(const fitting::LinearModel& lin, uint32_t j, uint32_t wrist) {
    for (const uint32_t a : lin.chains[j])
        if (a == wrist) return true;
    return false;
}

}  // namespace

TEST_CASE("a forearm made shorter or longer moves its wrist along it and holds every joint outside the hand", "[fitting][forearm]") {
    const Model& m = test::default_cpp_model();
    {
        // The whole body's components alone move both forearms together (and the rest of the body):
        // they cannot make one alone shorter.
        const fitting::LinearModel whole(m, m.component_count());
        CHECK(fitting::forearm_length_change(whole, std::vector<double>(whole.K, 0.0), 1, -0.03).empty());
    }
    {
        const bool segments = true;
        const fitting::LinearModel lin(m, m.component_count(), nullptr, segments);
        std::mt19937 rng(7);
        std::normal_distribution<double> draw(0.0, 1.0);
        std::vector<double> shape(lin.K);
        for (double& c : shape) c = draw(rng);
        for (int hand = 0; hand < 2; ++hand) {
            const uint32_t wrist = uint32_t(m.find_joint(hand == 0 ? "hand_l" : "hand_r"));
            const uint32_t elbow = lin.chains[wrist][1];
            for (const double metres : {-0.06, -0.03, 0.03}) {
                INFO((segments ? "with" : "without") << " segment components, hand " << hand << ", " << metres << " m");
                const std::vector<double> change = fitting::forearm_length_change(lin, shape, hand, metres);
                REQUIRE(change.size() == lin.K);
                std::vector<double> changed = shape;
                for (uint32_t k = 0; k < lin.K; ++k) changed[k] += change[k];
                const Vector3d along = (rest_joint(lin, shape, wrist) - rest_joint(lin, shape, elbow)).normalized();
                const Vector3d moved = rest_joint(lin, changed, wrist) - rest_joint(lin, shape, wrist);
                CHECK(moved.dot(along) == Approx(metres).margin(0.002));
                CHECK((moved - moved.dot(along) * along).norm() < 0.002);
                double held = 0;  // the largest move of a joint outside the hand
                for (uint32_t j = 0; j < lin.J; ++j)
                    if (!in_hand(lin, j, wrist)) held = std::max(held, (rest_joint(lin, changed, j) - rest_joint(lin, shape, j)).norm());
                CHECK(held < 0.002);
                // The least change that does it: a few standard deviations of the components, not tens.
                double norm = 0;
                for (const double c : change) norm += c * c;
                CHECK(std::sqrt(norm) < 10 * std::abs(metres) / 0.03);
            }
        }
    }
}

TEST_CASE("a rig without the hand's joint gets no forearm change", "[fitting][forearm]") {
    format::ModelData data = test::default_cpp_model().data();
    for (std::string& name : data.skeleton.joint_names)
        if (name == "hand_r") name = "palm_r";
    const Model renamed(data, nullptr);
    const fitting::LinearModel lin(renamed, renamed.component_count(), nullptr, true);
    CHECK(fitting::forearm_length_change(lin, std::vector<double>(lin.K, 0.0), 1, -0.03).empty());
    CHECK(fitting::forearm_length_change(lin, std::vector<double>(lin.K, 0.0), 0, -0.03).size() == lin.K);
}
