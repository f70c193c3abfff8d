#include "learning/evaluate_learning.hpp"

#include "common/error.hpp"
#include "common/rigid.hpp"
#include "fitting/kinematics.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace ssc::learning {

namespace {

std::vector<uint32_t> component_list(const std::vector<uint32_t>& asked, uint32_t reachable) {
    std::vector<uint32_t> ks;
    if (asked.empty()) {
        for (uint32_t k = 1; k <= 10; ++k) ks.push_back(k);
        for (uint32_t k = 15; k <= 50; k += 5) ks.push_back(k);
    } else {
        ks = asked;
    }
    std::vector<uint32_t> out;
    for (uint32_t k : ks)
        if (k >= 1 && k <= reachable) out.push_back(k);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

double mean_vertex_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    double sum = 0;
    for (Eigen::Index i = 0; i < a.size(); i += 3) sum += (a.segment<3>(i) - b.segment<3>(i)).norm();
    return sum / double(a.size() / 3);
}

// Identical bodies have no variance to learn: every curve would be 0 or NaN. Said before any work.
void require_bodies_that_differ(const training::SampleMatrix& bodies) {
    bool all_same = true;
    for (Eigen::Index i = 1; i < bodies.rows() && all_same; ++i) all_same = (bodies.row(i) - bodies.row(0)).cwiseAbs().maxCoeff() < 1e-6f;
    SSC_REQUIRE_ARG_S(!all_same, "evaluate: the " << bodies.rows() << " registrations are all the same body (within 1 micrometre): "
                                                  "there is no shape variation to learn (were the same scan's registrations given several times?)");
}

}  // namespace

std::vector<training::QualityPoint> evaluate_learning(const training::SampleMatrix& bodies, const EvaluationSpec& spec,
                                                      const EvaluationProgress& progress) {
    const Eigen::Index N = bodies.rows(), D = bodies.cols();
    SSC_REQUIRE_ARG_S(N >= 3, "evaluate: " << N << " registrations; at least 3");
    require_bodies_that_differ(bodies);
    const uint32_t folds = spec.folds ? spec.folds : uint32_t(N <= 100 ? N : 10);
    SSC_REQUIRE_ARG_S(folds >= 2 && folds <= uint32_t(N), "evaluate: " << folds << " folds for " << N << " registrations (2 to " << N << ")");
    // The smallest training set has N - ceil(N / folds) bodies: at most one fewer components.
    const uint32_t held_most = uint32_t((N + folds - 1) / folds), reachable = uint32_t(N) - held_most - 1;
    const std::vector<uint32_t> ks = component_list(spec.components, reachable);
    SSC_REQUIRE_ARG(!ks.empty(), "evaluate: no number of components within reach of this many registrations");
    const uint32_t K = ks.back();

    // Compactness and specificity: the model learned from every body.
    if (progress) progress("compactness and specificity from all " + std::to_string(N) + " registrations");
    training::SampleMatrix all = bodies;
    const training::Pca whole = training::pca(all, N, K, spec.seed);
    std::vector<training::QualityPoint> out = training::evaluate_quality(whole, all, training::SampleMatrix(0, D), ks, spec.samples, spec.seed);

    // Generalization: each fold reconstructed by the model learned without it.
    std::vector<double> sum(ks.size(), 0.0);
    for (uint32_t f = 0; f < folds; ++f) {
        if (progress) progress("generalization: fold " + std::to_string(f + 1) + " of " + std::to_string(folds));
        std::vector<Eigen::Index> train, held;
        for (Eigen::Index i = 0; i < N; ++i) (uint32_t(i % folds) == f ? held : train).push_back(i);
        training::SampleMatrix Xt(Eigen::Index(train.size()), D), Xh(Eigen::Index(held.size()), D);
        for (std::size_t i = 0; i < train.size(); ++i) Xt.row(Eigen::Index(i)) = bodies.row(train[i]);
        for (std::size_t i = 0; i < held.size(); ++i) Xh.row(Eigen::Index(i)) = bodies.row(held[i]);
        const training::Pca p = training::pca(Xt, Xt.rows(), K, spec.seed + f + 1);
        const std::vector<training::QualityPoint> q = training::evaluate_quality(p, Xt, Xh, ks, 0, spec.seed);
        for (std::size_t k = 0; k < ks.size(); ++k) sum[k] += q[k].generalization * double(held.size());
    }
    for (std::size_t k = 0; k < ks.size(); ++k) out[k].generalization = sum[k] / double(N);
    return out;
}

std::vector<SizedQuality> evaluate_training_sizes(const training::SampleMatrix& bodies, const std::vector<uint32_t>& sizes,
                                                  const EvaluationSpec& spec, const EvaluationProgress& progress) {
    const Eigen::Index N = bodies.rows(), D = bodies.cols();
    SSC_REQUIRE_ARG_S(N >= 10, "evaluate: " << N << " registrations; comparing training-set sizes needs at least 10");
    require_bodies_that_differ(bodies);
    std::vector<Eigen::Index> train, held;
    for (Eigen::Index i = 0; i < N; ++i) (i % 5 == 4 ? held : train).push_back(i);
    std::mt19937 rng(spec.seed);
    std::shuffle(train.begin(), train.end(), rng);
    training::SampleMatrix Xh(Eigen::Index(held.size()), D);
    for (std::size_t i = 0; i < held.size(); ++i) Xh.row(Eigen::Index(i)) = bodies.row(held[i]);
    std::vector<uint32_t> ns;
    for (uint32_t n : sizes) {
        SSC_REQUIRE_ARG_S(n == 0 || n >= 3, "evaluate: a training set of " << n << " registrations; at least 3");
        if (n == 0 || n > train.size()) n = n == 0 ? uint32_t(train.size()) : 0;
        if (n && std::find(ns.begin(), ns.end(), n) == ns.end()) ns.push_back(n);
    }
    std::sort(ns.begin(), ns.end());
    std::vector<SizedQuality> out;
    for (uint32_t n : ns) {
        const std::vector<uint32_t> ks = component_list(spec.components, n - 1);
        if (ks.empty()) continue;
        if (progress) progress("learning from " + std::to_string(n) + " registrations, " + std::to_string(held.size()) + " held out");
        training::SampleMatrix Xt(Eigen::Index(n), D);
        for (uint32_t i = 0; i < n; ++i) Xt.row(Eigen::Index(i)) = bodies.row(train[i]);
        const training::Pca p = training::pca(Xt, Xt.rows(), ks.back(), spec.seed);
        out.push_back({n, training::evaluate_quality(p, Xt, Xh, ks, spec.samples, spec.seed)});
    }
    return out;
}

std::vector<training::QualityPoint> evaluate_model(const format::ModelData& model, const training::SampleMatrix& bodies, const EvaluationSpec& spec) {
    const Eigen::Index N = bodies.rows(), D = bodies.cols();
    const uint32_t V = model.mesh.vertex_count, Kmodel = uint32_t(model.shape.stddev.size());
    SSC_REQUIRE_ARG_S(D == 3 * Eigen::Index(V), "evaluate: the bodies have " << D / 3 << " vertices; the model " << model.metadata.name << " has " << V);
    SSC_REQUIRE_ARG(N >= 1, "evaluate: no registrations");
    const std::vector<uint32_t> ks = component_list(spec.components, Kmodel);
    SSC_REQUIRE_ARG(!ks.empty(), "evaluate: no number of components within the model's");
    // The model's directions, metres per standard deviation (3V x K, vertex-major like the rows).
    const Model runtime(model, nullptr);
    const fitting::LinearModel lin(runtime, Kmodel);
    Eigen::MatrixXd B(D, Kmodel);
    for (Eigen::Index r = 0; r < D; ++r)
        for (uint32_t k = 0; k < Kmodel; ++k) B(r, k) = lin.basis[std::size_t(r) * Kmodel + k] * lin.step[k];
    Eigen::VectorXd mean(D);
    for (Eigen::Index i = 0; i < D; ++i) mean(i) = model.shape.mean[std::size_t(i)];

    // The bodies as 3 x V point sets, and the model's mean as one.
    std::vector<Eigen::Matrix3Xd> points(std::size_t(N), Eigen::Matrix3Xd(3, V));
    for (Eigen::Index i = 0; i < N; ++i)
        for (uint32_t v = 0; v < V; ++v) points[std::size_t(i)].col(v) = bodies.row(i).segment<3>(3 * v).transpose().cast<double>();
    Eigen::MatrixXd X(N, D);  // each body rigidly on the mean (for specificity's nearest body)
    Eigen::Matrix3Xd target(3, V);
    for (uint32_t v = 0; v < V; ++v) target.col(v) = mean.segment<3>(3 * v);
    for (Eigen::Index i = 0; i < N; ++i) {
        const Similarity T = align_points(points[std::size_t(i)], target, false);
        for (uint32_t v = 0; v < V; ++v) X.row(i).segment<3>(3 * v) = (T.R * points[std::size_t(i)].col(v) + T.t).transpose();
    }
    const Eigen::MatrixXd Xc = X.rowwise() - mean.transpose();
    const Eigen::VectorXd Xnorm = Xc.rowwise().squaredNorm();  // the c^T Bk^T Bk c term is the same for every body
    double total = 0, cum = 0;
    for (float s : model.shape.stddev) total += double(s) * s;
    std::vector<training::QualityPoint> out;
    std::mt19937 rng(spec.seed);
    std::normal_distribution<double> normal;
    uint32_t done = 0;
    for (uint32_t k : ks) {
        for (; done < k; ++done) cum += double(model.shape.stddev[done]) * model.shape.stddev[done];
        training::QualityPoint q;
        q.components = k;
        q.compactness = total > 0 ? cum / total : 0;
        // Generalization: the body's best approximation by the first k directions after a rigid
        // motion, by Gauss-Newton on (c, t, w): mean + Bk c ~ y + t + w x y, the small rotation w
        // applied exactly after each step. (A body unlike the mean is not best aligned to the mean,
        // and alternating alignment and coefficients crawls where a component is nearly rigid.)
        const Eigen::MatrixXd Bk = B.leftCols(k);
        const Eigen::MatrixXd BtB = Bk.transpose() * Bk;
        Eigen::MatrixXd Bsum = Eigen::MatrixXd::Zero(k, 3);  // sum over vertices of each axis' rows
        for (Eigen::Index r = 0; r < D; ++r) Bsum.col(r % 3) += Bk.row(r).transpose();
        double g = 0;
        for (Eigen::Index i = 0; i < N; ++i) {
            Eigen::VectorXd y = X.row(i).transpose(), fit = mean;
            for (int step = 0; step < 6; ++step) {
                const Eigen::Index n = Eigen::Index(k) + 6;
                Eigen::MatrixXd JtJ = Eigen::MatrixXd::Zero(n, n);
                Eigen::VectorXd Jtb = Eigen::VectorXd::Zero(n);
                const Eigen::VectorXd b = y - mean;
                JtJ.topLeftCorner(k, k) = BtB;
                JtJ.block(0, k, k, 3) = -Bsum;
                Jtb.head(k) = Bk.transpose() * b;
                // Bk^T [y]x from M(a, d), the k-vector sum_v Bk(3v + a, :) y_v[d]: nine products over
                // strided views.
                using Strided = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, 3>>;
                using StridedVec = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<3>>;
                Eigen::VectorXd M[3][3];
                for (int a = 0; a < 3; ++a) {
                    const Strided Ba(Bk.data() + a, V, k, Eigen::Stride<Eigen::Dynamic, 3>(D, 3));
                    for (int d = 0; d < 3; ++d) M[a][d] = Ba.transpose() * StridedVec(y.data() + d, V);
                }
                Eigen::MatrixXd Bcross(k, 3);
                Bcross.col(0) = M[1][2] - M[2][1];  // [y]x rows: (0, -z, y), (z, 0, -x), (-y, x, 0)
                Bcross.col(1) = M[2][0] - M[0][2];
                Bcross.col(2) = M[0][1] - M[1][0];
                Eigen::Matrix3d C = Eigen::Matrix3d::Zero(), S;
                Eigen::Vector3d ysum = Eigen::Vector3d::Zero(), bsum = Eigen::Vector3d::Zero(), bxy = Eigen::Vector3d::Zero();
                for (uint32_t v = 0; v < V; ++v) {
                    const Eigen::Vector3d yv = y.segment<3>(3 * v), bv = b.segment<3>(3 * v);
                    C += yv.squaredNorm() * Eigen::Matrix3d::Identity() - yv * yv.transpose();  // [y]x^T [y]x
                    ysum += yv, bsum += bv, bxy += bv.cross(yv);                                 // [y]x^T b = b x y
                }
                S << 0, -ysum.z(), ysum.y(), ysum.z(), 0, -ysum.x(), -ysum.y(), ysum.x(), 0;
                JtJ.block(0, k + 3, k, 3) = Bcross;
                JtJ.block(k, k, 3, 3) = double(V) * Eigen::Matrix3d::Identity();
                JtJ.block(k, k + 3, 3, 3) = -S;
                JtJ.block(k + 3, k + 3, 3, 3) = C;
                JtJ.bottomLeftCorner(6, k + 0) = JtJ.topRightCorner(k, 6).transpose();
                JtJ.block(k + 3, k, 3, 3) = JtJ.block(k, k + 3, 3, 3).transpose();
                Jtb.segment<3>(k) = -bsum;
                Jtb.segment<3>(k + 3) = bxy;
                const Eigen::VectorXd x = JtJ.ldlt().solve(Jtb);
                fit = mean + Bk * x.head(k);
                const Eigen::Vector3d t = x.segment<3>(k), w = x.segment<3>(k + 3);
                const Eigen::Matrix3d R = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
                for (uint32_t v = 0; v < V; ++v) y.segment<3>(3 * v) = R * y.segment<3>(3 * v) + t;
                if (w.norm() < 1e-9 && t.norm() < 1e-9) break;
            }
            g += mean_vertex_distance(fit, y);
        }
        q.generalization = g / double(N);
        // Specificity: the model's random bodies (N(0, 1) per component) against the nearest body,
        // found from ||x - mean - Bk c||^2 = |x - mean|^2 - 2 (x - mean)^T Bk c + c^T Bk^T Bk c.
        const Eigen::MatrixXd P = Xc * Bk;  // N x k
        double s = 0;
        for (uint32_t t = 0; t < spec.samples; ++t) {
            Eigen::VectorXd c(k);
            for (uint32_t j = 0; j < k; ++j) c(j) = normal(rng);
            const Eigen::VectorXd d = Xnorm - 2 * P * c;
            Eigen::Index nearest = 0;
            d.minCoeff(&nearest);
            const Eigen::VectorXd body = mean + Bk * c;
            s += mean_vertex_distance(X.row(nearest).transpose(), body);
        }
        q.specificity = spec.samples ? s / spec.samples : 0;
        out.push_back(q);
    }
    return out;
}

}  // namespace ssc::learning
