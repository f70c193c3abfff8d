#include "fitting/rigid_start.hpp"

#include "fitting/robust.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

namespace ssc::fitting {

namespace {

using Mat7 = Eigen::Matrix<double, 7, 7>;
using Vec7 = Eigen::Matrix<double, 7, 1>;

// Correspondences reach far (kStartReach) and the loss is wide.
constexpr double kLossScale = 10;  // Geman-McClure scale, in sigmas

struct Pair {
    uint32_t rest;     // index into the rest sample
    uint32_t scan;     // index into the cloud
    Vector3d normal;   // world frame, unit
    double weight;
};

double confidence(const CloudView& cloud, uint32_t i) { return cloud.confidence ? (*cloud.confidence)[i] : 1.0; }

// One candidate: Gauss-Newton on the similarity, then its score.
class Candidate {
public:
    Candidate(const RestSample& rest, const CloudView& cloud, const RigidStartOptions& o, const Vector3d& centre)
        : rest_(rest), cloud_(cloud), o_(o), centre_(centre) {}

    StartCandidate run(Similarity T) {
        for (int step = 0; step < o_.steps; ++step) T = gauss_newton_step(T);
        return {T, explained(T)};
    }

private:
    Vector3d posed(const Similarity& T, uint32_t k) const { return T.scale * (T.R * (*rest_.points)[k]) + T.t; }

    bool compatible(uint32_t i, const Vector3d& model_normal) const {
        return normals_agree((*cloud_.normals)[i], model_normal, cloud_.oriented, 0.0);
    }

    // Correspondences both ways, as the fitter's (solver.cpp, find_frame_pairs), with the scan
    // points carried into the rest frame for the model's fixed tree.
    void find_pairs(const Similarity& T) {
        pairs_.clear();
        const std::size_t n = std::max<std::size_t>(16, std::min(cloud_.sample->size(), o_.points));
        const double max2 = kStartReach * kStartReach;
        std::vector<std::pair<double, Pair>> found;
        std::vector<double> scratch;
        auto keep = [&]() {
            append_trimmed(found, scratch, pairs_);
            found.clear();
        };
        const Matrix3d to_rest = T.R.transpose() / T.scale;
        for (std::size_t s = 0; s < n; ++s) {
            const uint32_t i = (*cloud_.sample)[s];
            double d2;
            const uint32_t k = rest_.index->nearest(to_rest * ((*cloud_.points)[i] - T.t), &d2);
            d2 *= T.scale * T.scale;  // world units
            const Vector3d model_normal = T.R * (*rest_.normals)[k];
            const double w = confidence(cloud_, i);
            if (d2 > max2 || w <= 0 || !compatible(i, model_normal)) continue;
            found.push_back({d2, Pair{k, i, model_normal, w}});
        }
        keep();
        const std::size_t m = std::max<std::size_t>(16, std::min(rest_.points->size(), n));
        for (uint32_t k = 0; k < m && k < rest_.points->size(); ++k) {
            double d2;
            const uint32_t i = cloud_.coarse_grid->nearest(posed(T, k), kStartReach, &d2);
            if (i == GridIndex::kNone) continue;  // nothing within the reach
            const Vector3d model_normal = T.R * (*rest_.normals)[k];
            const double w = confidence(cloud_, i);
            if (w <= 0 || !compatible(i, model_normal)) continue;
            const Vector3d& scan_normal = (*cloud_.normals)[i];
            found.push_back({d2, Pair{k, i, scan_normal.squaredNorm() > 0 ? scan_normal : model_normal, 0.5 * w}});
        }
        keep();
    }

    // Parameters: a rotation w about the cloud's centre (world frame), a translation, and the log
    // of the scale when it is fitted.
    Similarity gauss_newton_step(const Similarity& T) {
        find_pairs(T);
        const int P = o_.fit_scale ? 7 : 6;
        Mat7 H = Mat7::Zero();
        Vec7 g = Vec7::Zero();
        Eigen::Matrix<double, 3, 7> J;
        for (const Pair& p : pairs_) {
            const double s = std::sqrt(p.weight) / o_.point_sigma;
            const Vector3d x = posed(T, p.rest);
            const PointPlaneTerm term = point_plane(s * (x - (*cloud_.points)[p.scan]), p.normal, kLossScale);
            const Vector3d r = x - centre_;
            J << 0, r.z(), -r.y(), 1, 0, 0, 0,  //
                -r.z(), 0, r.x(), 0, 1, 0, 0,   //
                r.y(), -r.x(), 0, 0, 0, 1, 0;   // d x / d w = -[r]x
            J.col(6) = x - T.t;                 // d x / d log scale
            J *= s;
            const Eigen::Matrix<double, 3, 7> LJ = term.L * J;
            H.noalias() += LJ.transpose() * LJ;
            g.noalias() += J.transpose() * term.m;
        }
        Eigen::MatrixXd A = H.topLeftCorner(P, P);
        for (int i = 0; i < P; ++i) A(i, i) += 1e-3 * std::max(A(i, i), 1e-9) + 1e-12;
        const Eigen::VectorXd d = A.ldlt().solve(-g.head(P));
        if (!d.allFinite()) return T;
        const Vector3d w = d.head<3>();
        const double angle = w.norm();
        const Matrix3d dR = angle > 0 ? Matrix3d(Eigen::AngleAxisd(angle, w / angle)) : Matrix3d::Identity();
        Similarity out;
        out.R = dR * T.R;
        out.scale = P == 7 ? T.scale * std::exp(d[6]) : T.scale;
        out.t = dR * (T.t - centre_) + centre_ + d.segment<3>(3);
        return out;
    }

    // The explained measure (explained.hpp) of the placed rest body, scan points looked up in the
    // rest frame.
    double explained(const Similarity& T) {
        placed_.resize(rest_.points->size());
        placed_normals_.resize(rest_.points->size());
        for (uint32_t k = 0; k < placed_.size(); ++k) placed_[k] = posed(T, k), placed_normals_[k] = T.R * (*rest_.normals)[k];
        const Matrix3d to_rest = T.R.transpose() / T.scale;
        return explained_measure(
            cloud_, placed_, placed_normals_, [&](const Vector3d& p) { return rest_.index->nearest(to_rest * (p - T.t), nullptr); },
            kPlacementCap, o_.samples);
    }

    const RestSample& rest_;
    const CloudView& cloud_;
    const RigidStartOptions& o_;
    Vector3d centre_;
    std::vector<Pair> pairs_;
    std::vector<Vector3d> placed_, placed_normals_;  // explained() scratch
};

}  // namespace

std::vector<StartCandidate> rigid_start(const RestSample& rest, const CloudView& cloud, const RigidStartOptions& o,
                                        ThreadPool& pool) {
    const auto& points = *cloud.points;
    Vector3d c = Vector3d::Zero();
    for (const auto& p : points) c += p;
    c /= double(points.size());
    Matrix3d cov = Matrix3d::Zero();
    for (const auto& p : points) cov += (p - c) * (p - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
    const Vector3d e1 = es.eigenvectors().col(2), e2 = es.eigenvectors().col(1), e3 = es.eigenvectors().col(0);
    const Vector3d& mc = rest.centre;
    const double lo = rest.bottom, hi = rest.top;
    double scale = 1;
    if (o.fit_scale) {
        double plo = 1e9, phi = -1e9;
        for (const auto& p : points) plo = std::min(plo, (p - c).dot(e1)), phi = std::max(phi, (p - c).dot(e1));
        scale = (phi - plo) / std::max(hi - lo, 1e-6);
    }
    std::vector<Similarity> starts;
    for (int sign = 1; sign >= -1; sign -= 2)
        for (int h = 0; h < 4; ++h) {
            const double a = h * M_PI / 2;
            const Vector3d y = double(sign) * e1;
            const Vector3d z = (std::cos(a) * e2 + std::sin(a) * e3).normalized();
            Similarity T;
            Matrix3d axes;
            axes.col(0) = y.cross(z);
            axes.col(1) = y;
            axes.col(2) = z;
            T.R = axes * rest.frame.transpose();
            T.scale = scale;
            T.t = c - scale * T.R * mc;
            starts.push_back(T);
        }
    std::vector<StartCandidate> out(starts.size());
    pool.parallel_for(starts.size(), [&](std::size_t i, unsigned) { out[i] = Candidate(rest, cloud, o, c).run(starts[i]); });
    std::stable_sort(out.begin(), out.end(), [](const StartCandidate& a, const StartCandidate& b) { return a.score < b.score; });
    return out;
}

}  // namespace ssc::fitting
