#include "fitting/forearm_length.hpp"

#include <Eigen/Cholesky>

namespace ssc::fitting {

namespace {

// Ridge of the least squares (square metres per squared component unit): small next to a joint's
// movement per component (about 1 cm), so the joints are held to well under a millimetre.
constexpr double kRidge = 1e-6;
// A change that leaves any joint further than this share of the move from where it was asked to be
// is not made.
constexpr double kMissedShare = 0.25;

Vector3d rest_joint(const LinearModel& lin, const std::vector<double>& shape, uint32_t j) {
    Vector3d x = lin.joint_mean[j];
    for (uint32_t a = 0; a < 3; ++a)
        for (uint32_t k = 0; k < lin.K && k < shape.size(); ++k) x[a] += lin.joint_basis[(std::size_t(j) * 3 + a) * lin.K + k] * shape[k];
    return x;
}

}  // namespace

std::vector<double> forearm_length_change(const LinearModel& lin, const std::vector<double>& shape, int hand, double metres) {
    const int64_t found = lin.model.find_joint(hand == 0 ? "hand_l" : "hand_r");
    if (found < 0 || lin.chains[std::size_t(found)].size() < 2) return {};
    const uint32_t wrist = uint32_t(found), elbow = lin.chains[wrist][1];
    const Vector3d along = (rest_joint(lin, shape, wrist) - rest_joint(lin, shape, elbow)).normalized();
    // Rows: every joint but the hand's own below the wrist (its fingers follow the wrist); the
    // wrist's rows ask for the move, the others for none.
    const uint32_t K = lin.K, J = lin.J;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * Eigen::Index(J), K);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * Eigen::Index(J));
    for (uint32_t j = 0; j < J; ++j) {
        bool in_hand = false;
        for (const uint32_t a : lin.chains[j]) in_hand |= a == wrist;
        if (in_hand && j != wrist) continue;
        for (uint32_t a = 0; a < 3; ++a) {
            for (uint32_t k = 0; k < K; ++k) A(3 * j + a, k) = lin.joint_basis[(std::size_t(j) * 3 + a) * K + k];
            if (j == wrist) b[3 * j + a] = metres * along[a];
        }
    }
    Eigen::MatrixXd normal = A.transpose() * A;
    normal.diagonal().array() += kRidge;
    const Eigen::VectorXd change = normal.ldlt().solve(A.transpose() * b);
    // Components that move every forearm together (a whole-body space without the arms' segment
    // spaces) can only trade the wrist's move for the other joints': no such change.
    const Eigen::VectorXd missed = A * change - b;
    if (missed.lpNorm<Eigen::Infinity>() > kMissedShare * std::abs(metres)) return {};
    return std::vector<double>(change.data(), change.data() + K);
}

}  // namespace ssc::fitting
