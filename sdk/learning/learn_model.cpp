#include "learning/learn_model.hpp"

#include "common/error.hpp"
#include "common/thread_pool.hpp"
#include "common/rigid.hpp"
#include "learning/laplacian_posture.hpp"
#include "learning/posture_fit.hpp"
#include "semantics/attribute_model.hpp"
#include "sscape_format/basis_codec.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"
#include "training/pca.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

namespace ssc::learning {

namespace {

// Known attributes beside the measurements: a collection records tens (sex, age, a few more);
// the attribute model's size and the slider search grow with the square of their count.
constexpr std::size_t kMaxKnownAttributes = 64;
constexpr double kMaxAttributeValue = 1e9;  // beyond any unit a person is described in

void check_inputs(const format::ModelData& t, const std::vector<scan_files::RegisteredScan>& scans, const LearnSpec& spec) {
    const uint32_t V = t.mesh.vertex_count;
    SSC_REQUIRE_ARG_S(scans.size() >= 3, "learn: " << scans.size() << " registrations; a shape space needs at least 3");
    SSC_REQUIRE_ARG_S(spec.components >= 1 && spec.components < scans.size(),
                      "learn: " << spec.components << " components from " << scans.size() << " registrations (at most " << scans.size() - 1 << ")");
    SSC_REQUIRE_ARG(std::isfinite(spec.tolerance) && spec.tolerance > 0 && spec.tolerance <= 1e-2, "learn: tolerance must be in (0, 0.01] m");
    SSC_REQUIRE_ARG(!spec.name.empty() && !spec.license.empty(), "learn: the model needs a name and a licence");
    for (const scan_files::RegisteredScan& s : scans) {
        SSC_REQUIRE_ARG_S(s.vertices.size() == V, "learn: " << s.name << " has " << s.vertices.size() << " vertices; the template has " << V
                                                            << " (was it registered with this model?)");
        for (const auto& x : s.vertices) SSC_REQUIRE_ARG_S(x.allFinite(), "learn: " << s.name << " has a vertex that is not finite");
        SSC_REQUIRE_ARG_S(spec.posture != Posture::Skeleton || s.has_fit,
                          "learn: " << s.name << " has no model fit, which the skeleton posture normalization needs");
    }
    if (spec.segment_components > 0) {
        SSC_REQUIRE_ARG_S(spec.segment_components < scans.size(), "learn: " << spec.segment_components << " components per segment from "
                                                                             << scans.size() << " registrations (at most " << scans.size() - 1 << ")");
        SSC_REQUIRE_ARG_S(spec.segment_band >= 0.005 && spec.segment_band <= 0.5, "learn: the segments' blend band is " << spec.segment_band << " m; it must lie in [0.005, 0.5]");
        training::segment_layout(t, spec.segment_band);  // refuses a template without body parts now, not after the PCA
    }
    if (spec.posture == Posture::Skeleton && spec.posture_model) check_posture_model(t, *spec.posture_model);
    // The same body again and again: the PCA would find no variance and the model would fail its
    // own validation with a message about covariances; say what is wrong with the input instead.
    bool all_same = true;
    for (std::size_t i = 1; i < scans.size() && all_same; ++i)
        for (std::size_t v = 0; v < V && all_same; ++v) all_same = (scans[i].vertices[v] - scans[0].vertices[v]).squaredNorm() < 1e-12;
    SSC_REQUIRE_ARG_S(!all_same, "learn: the " << scans.size() << " registrations are all the same body (within 1 micrometre): a shape space "
                                               "needs bodies that differ (were the same scan's registrations given several times?)");
    SSC_REQUIRE_ARG_S(spec.attributes.size() <= kMaxKnownAttributes,
                      "learn: " << spec.attributes.size() << " attributes; at most " << kMaxKnownAttributes << " are learned beside the shape");
    for (std::size_t i = 0; i < spec.attributes.size(); ++i) {
        const auto& a = spec.attributes[i];
        SSC_REQUIRE_ARG_S(!a.name.empty(), "learn: an attribute has no name");
        for (std::size_t k = 0; k < i; ++k) SSC_REQUIRE_ARG_S(spec.attributes[k].name != a.name, "learn: attribute " << a.name << " is given twice");
        SSC_REQUIRE_ARG_S(a.values.size() == scans.size(), "learn: attribute " << a.name << " has " << a.values.size() << " values for "
                                                                             << scans.size() << " registrations");
        for (double x : a.values) {
            SSC_REQUIRE_ARG_S(std::isfinite(x), "learn: attribute " << a.name << " has a value that is not finite");
            SSC_REQUIRE_ARG_S(std::abs(x) <= kMaxAttributeValue, "learn: attribute " << a.name << " has the value " << x << "; values lie within +-" << kMaxAttributeValue);
        }
        const auto [lo, hi] = std::minmax_element(a.values.begin(), a.values.end());
        SSC_REQUIRE_ARG_S(*hi - *lo > 1e-12 * std::max(1.0, std::abs(*hi)),
                          "learn: attribute " << a.name << " is " << *lo << " for every registration: it tells nothing about shape (leave its column out)");
    }
}

// Turns and moves every body (rows of X) by the one rigid motion that best takes their mean onto
// the template's mean, then lifts them so that the mean's lowest point is the template mean's: the
// learned model keeps the template's frame (facing +Z, standing on its ground), which its
// skeleton's rest orientations and users' scenes assume. (Matching centroids alone would float a
// population shorter than the template above the ground.)
void align_to_template(training::SampleMatrix& X, const format::ModelData& t) {
    const Eigen::Index V = Eigen::Index(t.mesh.vertex_count);
    Eigen::Matrix3Xd src(3, V), dst(3, V);
    const Eigen::RowVectorXd mean = X.cast<double>().colwise().mean();
    for (Eigen::Index v = 0; v < V; ++v) {
        src.col(v) = mean.segment<3>(3 * v).transpose();
        dst.col(v) = Eigen::Vector3d(t.shape.mean[std::size_t(3 * v)], t.shape.mean[std::size_t(3 * v + 1)], t.shape.mean[std::size_t(3 * v + 2)]);
    }
    Similarity T = align_points(src, dst, false);
    const Eigen::Matrix3Xd moved = (T.R * src).colwise() + T.t;
    T.t.y() += dst.row(1).minCoeff() - moved.row(1).minCoeff();
    for (Eigen::Index i = 0; i < X.rows(); ++i)
        for (Eigen::Index v = 0; v < V; ++v) {
            const Eigen::Vector3d x = T.R * Eigen::Vector3d(X(i, 3 * v), X(i, 3 * v + 1), X(i, 3 * v + 2)) + T.t;
            for (int a = 0; a < 3; ++a) X(i, 3 * v + a) = float(x[a]);
        }
}

}  // namespace

training::SampleMatrix normalized_bodies(const Model& model, const std::vector<scan_files::RegisteredScan>& scans, Posture posture, bool scale,
                                         uint32_t threads, const Model* posture_model) {
    const Model& rig = posture_model ? *posture_model : model;
    const uint32_t N = uint32_t(scans.size()), V = model.vertex_count();
    for (const scan_files::RegisteredScan& s : scans) {
        SSC_REQUIRE_ARG_S(s.vertices.size() == V, "learn: " << s.name << " has " << s.vertices.size() << " vertices; the model has " << V);
        SSC_REQUIRE_ARG_S(posture != Posture::Skeleton || s.has_fit, "learn: " << s.name << " has no model fit");
    }
    training::SampleMatrix X(N, 3 * Eigen::Index(V));
    std::unique_ptr<const LaplacianPosture> laplacian;
    if (posture == Posture::Laplacian) laplacian = std::make_unique<const LaplacianPosture>(model);
    // Each body on its own (the model and the factorisation are only read), each row written by
    // one worker; the first failure is rethrown after the join.
    ThreadPool pool(threads ? threads : std::max(1u, std::thread::hardware_concurrency()));
    std::mutex failure_mutex;
    std::exception_ptr failure;
    pool.parallel_for(N, [&](std::size_t i, unsigned) {
        try {
            const std::vector<Eigen::Vector3d> rest = posture == Posture::Skeleton    ? unpose_skeleton(rig, scans[i].fit, scans[i].vertices)
                                                      : posture == Posture::Laplacian ? laplacian->unpose(scans[i].vertices)
                                                                                      : scans[i].vertices;
            for (uint32_t v = 0; v < V; ++v)
                for (int a = 0; a < 3; ++a) X(Eigen::Index(i), 3 * Eigen::Index(v) + a) = float(rest[v][a]);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
        }
    });
    if (failure) std::rethrow_exception(failure);
    training::procrustes_align(X, 5, scale);
    align_to_template(X, model.data());
    return X;
}

format::ModelData learn_model(const format::ModelData& template_model, const std::vector<scan_files::RegisteredScan>& scans, const LearnSpec& spec,
                              LearnReport* report, const LearnProgress& progress) {
    auto say = [&](const std::string& stage) {
        if (progress) progress(stage);
    };
    check_inputs(template_model, scans, spec);
    const Model model(template_model, nullptr);
    const uint32_t N = uint32_t(scans.size()), V = model.vertex_count();
    const bool own_posture_model = spec.posture == Posture::Skeleton && spec.posture_model;
    std::unique_ptr<const Model> posture_model;
    if (own_posture_model) posture_model = std::make_unique<const Model>(*spec.posture_model, nullptr);

    say(std::string("posture normalization: ") + posture_name(spec.posture) + (own_posture_model ? " (poses of '" + spec.posture_model->metadata.name + "')" : "") +
        (spec.scale ? ", Procrustes alignment with scale" : ", Procrustes alignment"));
    training::SampleMatrix X = normalized_bodies(model, scans, spec.posture, spec.scale, spec.threads, posture_model.get());

    say("PCA of " + std::to_string(N) + " registrations");
    const training::Pca p = training::pca(X, N, spec.components, spec.seed);
    const uint32_t K = uint32_t(p.basis.cols());

    format::ModelData m = template_model;
    m.metadata.name = spec.name;
    m.metadata.model_version = "0.1";
    m.metadata.license = spec.license;
    m.metadata.description = "Body shape space (S-SCAPE) learned from " + std::to_string(N) + " registered scans.";
    std::ostringstream prov;
    prov << "Learned from " << N << " registrations of model '" << template_model.metadata.name
         << "'; posture normalization " << posture_name(spec.posture)
         << (own_posture_model ? " with the poses of model '" + spec.posture_model->metadata.name + "'" : std::string()) << (spec.scale ? "; Procrustes with scale (sizes removed)" : "") << "; " << K
         << " components";
    if (!spec.provenance.empty()) prov << "\n" << spec.provenance;
    m.metadata.provenance = prov.str();
    m.shape.mean.assign(p.mean.data(), p.mean.data() + p.mean.size());
    m.shape.stddev.resize(K);
    std::vector<float> scaled(std::size_t(K) * 3 * V);  // planar, metres per standard deviation
    for (uint32_t k = 0; k < K; ++k) {
        m.shape.stddev[k] = float(p.stddev(k));
        for (uint32_t v = 0; v < V; ++v)
            for (int c = 0; c < 3; ++c) scaled[std::size_t(k) * 3 * V + std::size_t(c) * V + v] = float(p.stddev(k)) * p.basis(3 * v + c, k);
    }
    say("quantizing the basis");
    format::QuantizeReport quantization;
    m.shape.basis = format::quantize_basis(scaled.data(), V, K, spec.tolerance, &quantization);
    m.attributes = {};
    say("measuring every registration for the attribute model");
    m.attributes = training::learn_attribute_model(m, X, p, N, spec.attributes);
    // Sliders must be independent of each other, in the data and in the shape space (at most K of
    // them), or the runtime refuses the model. A small or correlated collection does not guarantee
    // that, so each slider is kept, in order (measurements first), only while the set stays usable;
    // the others stay attributes (they still condition made to measure).
    std::vector<std::string> sliders, not_sliders;
    std::vector<std::size_t> wanted;
    for (std::size_t a = 0; a < m.attributes.attributes.size(); ++a)
        if (m.attributes.attributes[a].slider) wanted.push_back(a), m.attributes.attributes[a].slider = false;
    for (std::size_t a : wanted) {
        format::Attribute& at = m.attributes.attributes[a];
        at.slider = true;
        try {
            const semantics::AttributeModel check(m);
            sliders.push_back(at.name);
        } catch (const Error&) {
            at.slider = false;
            not_sliders.push_back(at.name);
        }
    }
    std::vector<training::SegmentCompactness> segment_compactness;
    if (spec.segment_components > 0) {
        say("PCA per body segment");
        training::SegmentSpec segments;
        segments.components = spec.segment_components;
        segments.band = spec.segment_band;
        segments.tolerance = spec.tolerance;
        segments.seed = spec.seed;
        m.segments = training::learn_segments(m, X, N, p, segments, &segment_compactness);
        m.metadata.provenance += "\nsegment shape spaces: " + std::to_string(spec.segment_components) + " components each, blend band " +
                                 std::to_string(int(std::lround(spec.segment_band * 1000))) + " mm";
    } else {
        m.segments.clear();
    }
    format::validate_model(m);

    if (report) {
        report->segments = segment_compactness;
        report->bodies = N;
        report->components = K;
        report->stddev.assign(p.stddev.data(), p.stddev.data() + p.stddev.size());
        report->total_variance = p.total_variance;
        double kept = 0;
        for (double s : report->stddev) kept += s * s;
        report->explained = p.total_variance > 0 ? kept / p.total_variance : 0;
        report->quantization_error = quantization.max_error;
        report->sliders = sliders;
        report->not_sliders = not_sliders;
    }
    return m;
}

format::ModelData template_only(const format::ModelData& model) {
    format::ModelData m = model;
    m.shape.stddev.clear();
    m.shape.basis.components = 0;
    m.shape.basis.step.clear();
    m.shape.basis.q.clear();
    m.attributes = {};
    m.segments.clear();
    m.metadata.name = model.metadata.name + " (template only)";
    m.metadata.provenance = "The template of '" + model.metadata.name + "' alone, without its shape space.\n" + model.metadata.provenance;
    format::validate_model(m);
    return m;
}

}  // namespace ssc::learning
