// Shape statistics: rigid generalized Procrustes alignment and PCA by randomized SVD.
#pragma once

#include <Eigen/Core>

#include <cstdint>

namespace ssc::training {

// Samples as rows: N bodies x 3V coordinates (x y z per vertex).
using SampleMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Generalized Procrustes alignment: each body is rotated and translated (and with_scale, scaled)
// onto the running mean (Kabsch; Umeyama) until the mean settles. With scale the mean keeps the
// bodies' average size, so the aligned bodies differ in shape only. In place.
void procrustes_align(SampleMatrix& X, int iterations = 5, bool with_scale = false);

struct Pca {
    Eigen::VectorXf mean;     // 3V
    Eigen::MatrixXf basis;    // 3V x K, orthonormal columns (principal directions)
    Eigen::VectorXd stddev;   // K: standard deviation of each coefficient
    double total_variance = 0;  // sum over all directions (per-sample variance, N - 1 normalised)
};

// Top-K principal components of the first `rows` rows of X (centred in place; the rest untouched)
// by randomized SVD (Halko, Martinsson and Tropp 2011) with `power` power iterations and 10 extra
// directions.
Pca pca(SampleMatrix& X, Eigen::Index rows, uint32_t K, uint32_t seed, int power = 3);

}  // namespace ssc::training
