// The `laplacian` posture normalization (after Wuhrer, Shu and Xi): a registration's shape kept
// in differential coordinates that do not see posture, rebuilt in the rest posture of the model's
// mean. It needs no model fit, unlike the skeleton method.
//
// A vertex's localized coordinates are its one-ring edge vectors y_i - y_j, laid down in a frame
// R_i of its own. The rebuilt body x minimises, over x and the frames, starting from the mean mu
// at rest,
//   sum_i [ sum_{j in N(i)} w_ij |(x_i - x_j) - R_i (y_i - y_j)|^2 + posture s_i |R_i - T_i|_F^2 ]
//   + anchor sum_i m_i |x_i - mu_i|^2
// (an as-rigid-as-possible energy, Sorkine and Alexa, alternating frames and positions). The
// coordinates alone leave posture free; the frames' targets T_i set it: each skinning segment of
// the registration (a joint's vertices, weighted by the template's skin weights) is turned by the
// rotation that best takes it onto the mean's segment, and T_i blends those rotations as the skin
// weights blend the joints. So each limb ends oriented as the mean's is, bent joints straighten,
// and the surface between is rebuilt from the registration's own coordinates (no skinning
// artefacts). s_i = sum_j w_ij |y_i - y_j|^2 makes the posture weight independent of scale;
// w_ij are the mean's cotangent weights and m_i its vertex areas (mean 1); the anchor only fixes
// where the body stands. docs/learning.md has the measurements.
#pragma once

#include "synthesis/model.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCholesky>

#include <memory>
#include <vector>

namespace ssc::learning {

struct LaplacianPostureOptions {
    double posture = 1;            // weight of the frames' targets (the segments' rotations onto the mean's)
    double anchor = 1e-6;          // weight of the mean's position: where the body stands
    uint32_t max_iterations = 100; // frame/position alternations
    double tolerance = 1e-5;       // stop when no vertex moves further (metres)
};

class LaplacianPosture {
public:
    // Weights, areas and the factorisation of the global step, from the model's mean at rest.
    // Throws ssc::Error (INVALID_ARGUMENT) for options out of range.
    explicit LaplacianPosture(const Model& model, const LaplacianPostureOptions& options = {});
    ~LaplacianPosture();
    LaplacianPosture(const LaplacianPosture&) = delete;
    LaplacianPosture& operator=(const LaplacianPosture&) = delete;

    // `posed` (the model's vertex order, any rigid placement, metres) rebuilt in the rest posture.
    // Throws ssc::Error (INVALID_ARGUMENT) for a wrong vertex count or non-finite values.
    std::vector<Eigen::Vector3d> unpose(const std::vector<Eigen::Vector3d>& posed) const;

private:
    LaplacianPostureOptions options_;
    std::vector<uint32_t> first_, neighbour_;  // one-ring adjacency (CSR)
    std::vector<double> weight_;               // w_ij per adjacency entry
    Eigen::MatrixX3d mean_;                    // mu, the start
    std::vector<double> anchor_weight_;        // anchor * m_i per vertex
    std::size_t segment_count_ = 0;            // the skeleton's joints: one rigid segment each
    std::vector<double> skin_weight_;          // the template's skinning, 4 per vertex
    std::vector<uint32_t> skin_joint_;
    std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> solver_;
};

}  // namespace ssc::learning
