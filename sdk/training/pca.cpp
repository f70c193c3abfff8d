#include "pca.hpp"

#include "common/rigid.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>

#include <cmath>
#include <random>

namespace ssc::training {

void procrustes_align(SampleMatrix& X, int iterations, bool with_scale) {
    const Eigen::Index N = X.rows(), V = X.cols() / 3;
    auto body = [&](Eigen::Index i) { return Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(X.row(i).data(), V, 3); };
    Eigen::MatrixX3d mean = body(0).cast<double>();
    // With scale, the mean keeps the bodies' average size (RMS distance from the centroid), or
    // aligning every body onto it would shrink it round after round.
    double size = 0;
    if (with_scale)
        for (Eigen::Index i = 0; i < N; ++i) {
            const Eigen::MatrixX3d b = body(i).cast<double>();
            size += std::sqrt((b.rowwise() - b.colwise().mean()).squaredNorm() / double(V)) / double(N);
        }
    for (int it = 0; it < iterations; ++it) {
        const Eigen::RowVector3d mc = mean.colwise().mean();
        const Eigen::MatrixX3d centred_mean = mean.rowwise() - mc;
        Eigen::MatrixX3d next = Eigen::MatrixX3d::Zero(V, 3);
        for (Eigen::Index i = 0; i < N; ++i) {
            auto b = body(i);
            const Eigen::RowVector3d c = b.cast<double>().colwise().mean();
            const Eigen::MatrixX3d p = b.cast<double>().rowwise() - c;
            // Kabsch (Umeyama with scale): the rotation (and scale) taking the centred body onto the centred mean.
            const Similarity S = align_points(p.transpose(), centred_mean.transpose(), with_scale);
            const Eigen::MatrixX3d aligned = (S.scale * p * S.R.transpose()).rowwise() + mc;
            b = aligned.cast<float>();
            next += aligned;
        }
        mean = next / double(N);
        if (with_scale) {
            const Eigen::RowVector3d c = mean.colwise().mean();
            const double mean_size = std::sqrt((mean.rowwise() - c).squaredNorm() / double(V));
            mean = ((mean.rowwise() - c) * (size / mean_size)).rowwise() + c;
        }
    }
}

Pca pca(SampleMatrix& all, Eigen::Index rows, uint32_t K, uint32_t seed, int power) {
    auto X = all.topRows(rows);
    const Eigen::Index N = X.rows(), D = X.cols();
    Pca out;
    out.mean = X.colwise().mean().transpose();
    X.rowwise() -= out.mean.transpose();
    out.total_variance = double(X.cast<double>().squaredNorm()) / double(N - 1);

    const Eigen::Index l = std::min<Eigen::Index>(Eigen::Index(K) + 10, std::min(N, D));
    std::mt19937 rng(seed);
    std::normal_distribution<float> normal;
    Eigen::MatrixXf omega(N, l);
    for (Eigen::Index i = 0; i < omega.size(); ++i) omega.data()[i] = normal(rng);
    // Range of X^T (the principal directions), sharpened by power iterations.
    Eigen::MatrixXf Y = X.transpose() * omega;  // D x l
    for (int p = 0; p < power; ++p) {
        Eigen::HouseholderQR<Eigen::MatrixXf> qr(Y);
        Y = qr.householderQ() * Eigen::MatrixXf::Identity(D, l);
        const Eigen::MatrixXf Z = X * Y;  // N x l
        Y = X.transpose() * Z;
    }
    Eigen::HouseholderQR<Eigen::MatrixXf> qr(Y);
    const Eigen::MatrixXf Q = qr.householderQ() * Eigen::MatrixXf::Identity(D, l);
    const Eigen::MatrixXd B = (X * Q).cast<double>();  // N x l
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinV);
    const Eigen::Index k = std::min<Eigen::Index>(K, l);
    out.basis = Q * svd.matrixV().leftCols(k).cast<float>();
    out.stddev = svd.singularValues().head(k) / std::sqrt(double(N - 1));
    return out;
}

}  // namespace ssc::training
