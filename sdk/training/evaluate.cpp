#include "evaluate.hpp"

#include "common/files.hpp"
#include "render/plot.hpp"

#include <Eigen/Dense>

#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace ssc::training {
namespace {

// Mean over vertices of the Euclidean distance between two bodies (3V vectors).
double mean_vertex_distance(const float* a, const float* b, Eigen::Index coords) {
    double sum = 0;
    for (Eigen::Index i = 0; i < coords; i += 3) {
        const double dx = double(a[i]) - b[i], dy = double(a[i + 1]) - b[i + 1], dz = double(a[i + 2]) - b[i + 2];
        sum += std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    return sum / double(coords / 3);
}

}  // namespace

std::vector<QualityPoint> evaluate_quality(const Pca& p, const SampleMatrix& training, const SampleMatrix& heldout,
                                           const std::vector<uint32_t>& ks, uint32_t samples, uint32_t seed) {
    const Eigen::Index D = p.mean.size(), K = p.basis.cols();
    // Coefficients of every training and held-out body on all K components (metres along each unit
    // direction): the nearest-neighbour search and the reconstructions work from these.
    const Eigen::MatrixXf train_coef = training * p.basis;  // N x K
    const SampleMatrix held_centred = heldout.rowwise() - p.mean.transpose();
    const Eigen::MatrixXf held_coef = held_centred * p.basis;
    // Squared residual of each training body outside the K components, for the search bound.
    Eigen::VectorXd train_resid(training.rows());
    for (Eigen::Index i = 0; i < training.rows(); ++i)
        train_resid(i) = std::max(0.0, double(training.row(i).squaredNorm()) - double(train_coef.row(i).squaredNorm()));

    std::vector<QualityPoint> out;
    double cum = 0;
    std::vector<double> cumulative(K);
    for (Eigen::Index k = 0; k < K; ++k) cumulative[k] = (cum += p.stddev(k) * p.stddev(k));
    std::mt19937 rng(seed);
    std::normal_distribution<double> normal;
    std::vector<float> body(D), other(D);
    for (uint32_t k : ks) {
        if (k == 0 || k > K) continue;
        QualityPoint q;
        q.components = k;
        q.compactness = cumulative[k - 1] / p.total_variance;
        // Generalization: reconstruct held-out bodies from k components.
        double g = 0;
        for (Eigen::Index i = 0; i < heldout.rows(); ++i) {
            Eigen::Map<Eigen::VectorXf>(body.data(), D) = p.mean + p.basis.leftCols(k) * held_coef.row(i).head(k).transpose();
            g += mean_vertex_distance(body.data(), heldout.row(i).data(), D);
        }
        q.generalization = heldout.rows() ? g / double(heldout.rows()) : 0;
        // Specificity: nearest training body (by squared distance, computed in coefficient space)
        // to each random sample, then the mean vertex distance to it.
        double s = 0;
        for (uint32_t t = 0; t < samples; ++t) {
            Eigen::VectorXf c = Eigen::VectorXf::Zero(K);
            for (uint32_t i = 0; i < k; ++i) c(i) = float(p.stddev(i) * normal(rng));
            Eigen::Index best = 0;
            double best_d = std::numeric_limits<double>::max();
            for (Eigen::Index n = 0; n < training.rows(); ++n) {
                const double d = double((train_coef.row(n).transpose() - c).squaredNorm()) + train_resid(n);
                if (d < best_d) best_d = d, best = n;
            }
            Eigen::Map<Eigen::VectorXf>(body.data(), D) = p.basis * c;  // centred sample
            s += mean_vertex_distance(body.data(), training.row(best).data(), D);
        }
        q.specificity = samples ? s / samples : 0;
        out.push_back(q);
    }
    return out;
}

std::vector<std::string> write_quality_report(const std::string& prefix, const std::vector<QualityPoint>& q) {
    std::ostringstream csv;
    csv << "components,compactness,generalization_mm,specificity_mm\n";
    for (const auto& p : q) csv << p.components << "," << p.compactness << "," << p.generalization * 1e3 << "," << p.specificity * 1e3 << "\n";
    const std::string text = csv.str(), csv_path = prefix + "quality.csv";
    write_file_atomically(csv_path, text.data(), text.size());
    std::vector<std::string> pngs;
    render::LinePlot plots[3];
    plots[0] = {"compactness", "number of components", "cumulative explained variance", {}, {}, {}, {}};
    plots[1] = {"generalization", "number of components", "held-out mean vertex error (mm)", {}, {}, {}, {}};
    plots[2] = {"specificity", "number of components", "distance to nearest training body (mm)", {}, {}, {}, {}};
    for (const auto& point : q) {
        for (auto& plot : plots) plot.x.push_back(point.components);
        plots[0].y.push_back(point.compactness);
        plots[1].y.push_back(point.generalization * 1e3);
        plots[2].y.push_back(point.specificity * 1e3);
    }
    if (q.empty()) return pngs;
    for (const auto& plot : plots) {
        pngs.push_back(prefix + plot.title + ".png");
        render::write_line_plot(pngs.back(), plot);
    }
    return pngs;
}

}  // namespace ssc::training
