// Learning models from registered scans: posture normalization, the learned shape space, bad input.
#include "learning/evaluate_learning.hpp"
#include "learning/learn_model.hpp"
#include "learning/laplacian_posture.hpp"
#include "learning/posture_normalization.hpp"
#include "support.hpp"

#include "capi/cpp_access.hpp"
#include "common/error.hpp"
#include "common/rigid.hpp"
#include "semantics/attribute_model.hpp"
#include "simulation/simulate.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace ssc;
using Eigen::Vector3d;

namespace {

std::vector<float> identity_pose(const Model& m) {
    std::vector<float> q(4 * std::size_t(m.joint_count()), 0.f);
    for (uint32_t j = 0; j < m.joint_count(); ++j) q[4 * j + 3] = 1.f;
    return q;
}

// A body of the model's first `components` shape directions, posed and placed at random, as a
// perfect registration with the fit that found it.
struct Sample {
    scan_files::RegisteredScan scan;
    std::vector<Vector3d> rest;  // the same body at rest, at the origin
};

Sample sample(const Model& m, std::mt19937& rng, uint32_t components, double pose_amount) {
    std::vector<float> shape = simulation::random_shape(m, rng);
    for (std::size_t k = components; k < shape.size(); ++k) shape[k] = 0;
    const std::vector<float> pose = simulation::random_pose(m, rng, pose_amount);
    std::uniform_real_distribution<double> offset(-0.5, 0.5);
    const Vector3d t(offset(rng), offset(rng) * 0.1, offset(rng));
    const simulation::TrueBody posed = simulation::make_body(m, shape, pose, t);
    Sample s;
    s.scan.name = "body";
    s.scan.vertices = posed.vertices;
    s.scan.has_fit = true;
    s.scan.fit.shape.assign(shape.begin(), shape.end());
    for (uint32_t j = 0; j < m.joint_count(); ++j)
        s.scan.fit.pose.emplace_back(pose[4 * j + 3], pose[4 * j], pose[4 * j + 1], pose[4 * j + 2]);
    s.scan.fit.translation = t;
    s.rest = simulation::make_body(m, shape, identity_pose(m), Vector3d::Zero()).vertices;
    return s;
}

}  // namespace

TEST_CASE("skeleton posture normalization undoes the fitted skinning", "[learning]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(5);
    const Sample s = sample(m, rng, m.component_count(), 0.8);
    const std::vector<Vector3d> rest = learning::unpose_skeleton(m, s.scan.fit, s.scan.vertices);
    double worst = 0, moved = 0;
    for (std::size_t v = 0; v < rest.size(); ++v) {
        worst = std::max(worst, (rest[v] - s.rest[v]).norm());
        moved = std::max(moved, (s.scan.vertices[v] - s.rest[v]).norm());
    }
    CHECK(moved > 0.1);     // the pose moved the body
    CHECK(worst < 2e-5);    // and unposing brings it back (float synthesis)
    // With a scale, as a fit in unknown units reports it.
    scan_files::RegisteredScan scaled = s.scan;
    scaled.fit.scale = 1.7;
    for (auto& x : scaled.vertices) x = 1.7 * (x - s.scan.fit.translation) + s.scan.fit.translation;
    const std::vector<Vector3d> again = learning::unpose_skeleton(m, scaled.fit, scaled.vertices);
    worst = 0;
    for (std::size_t v = 0; v < rest.size(); ++v) worst = std::max(worst, (again[v] - s.rest[v]).norm());
    CHECK(worst < 2e-5);
    // A fit with the segment shape spaces (a registration's, by default): the skeleton follows them too.
    fitting::FitState segmented = s.scan.fit;
    segmented.shape.resize(m.component_count(), 0.0);
    for (std::size_t i = 0; i < m.segment_coefficient_count(); ++i) segmented.shape.push_back(i % 3 == 0 ? 1.5 : -0.5);
    fitting::FitState at_rest = segmented;
    for (auto& q : at_rest.pose) q = Eigen::Quaterniond::Identity();
    at_rest.translation.setZero();
    at_rest.scale = 1;
    const std::vector<Vector3d> segmented_rest = simulation::fitted_vertices(m, at_rest);
    const std::vector<Vector3d> unposed = learning::unpose_skeleton(m, segmented, simulation::fitted_vertices(m, segmented));
    worst = moved = 0;
    for (std::size_t v = 0; v < rest.size(); ++v) {
        worst = std::max(worst, (unposed[v] - segmented_rest[v]).norm());
        moved = std::max(moved, (segmented_rest[v] - s.rest[v]).norm());
    }
    CHECK(moved > 0.01);  // the segments changed the body
    CHECK(worst < 2e-5);
    // Bad input.
    std::vector<Vector3d> short_list(s.scan.vertices.begin(), s.scan.vertices.end() - 1);
    CHECK_THROWS_AS(learning::unpose_skeleton(m, s.scan.fit, short_list), Error);
    fitting::FitState bad = s.scan.fit;
    bad.pose[3] = Eigen::Quaterniond(std::nan(""), 0, 0, 0);
    CHECK_THROWS_AS(learning::unpose_skeleton(m, bad, s.scan.vertices), Error);
    bad = s.scan.fit;
    bad.scale = 0;
    CHECK_THROWS_AS(learning::unpose_skeleton(m, bad, s.scan.vertices), Error);
    CHECK(learning::posture_from_name("none") == learning::Posture::None);
    CHECK_THROWS_AS(learning::posture_from_name("laplace"), Error);
}

TEST_CASE("laplacian posture normalization drops posture without a fit and keeps the registration's surface", "[learning]") {
    const Model& m = test::default_cpp_model();
    const learning::LaplacianPosture laplacian(m);
    // Mean vertex distance after the best rigid motion (learning aligns bodies rigidly anyway).
    auto apart = [](const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
        Eigen::Matrix3Xd src(3, a.size()), dst(3, a.size());
        for (std::size_t v = 0; v < a.size(); ++v) src.col(Eigen::Index(v)) = a[v], dst.col(Eigen::Index(v)) = b[v];
        const Similarity T = align_points(src, dst, false);
        return ((T.R * src).colwise() + T.t - dst).colwise().norm().mean();
    };
    std::mt19937 rng(5);
    for (double amount : {0.15, 0.6}) {  // a booth's variation; bent elbows and knees
        const Sample s = sample(m, rng, m.component_count(), amount);
        const std::vector<Vector3d> from_posed = laplacian.unpose(s.scan.vertices), from_rest = laplacian.unpose(s.rest);
        const double posed = apart(s.scan.vertices, s.rest), left = apart(from_posed, from_rest), shape = apart(from_rest, s.rest);
        INFO("pose " << amount << ": posed body " << posed * 1e3 << " mm from its rest, normalized " << left * 1e3
                     << " mm from the normalized rest body, which is " << shape * 1e3 << " mm from the rest body");
        CHECK(posed > 0.03);
        CHECK(left < (amount < 0.5 ? 0.1 : 0.15) * posed);  // posture mostly gone
        CHECK(shape < 0.015);  // limbs turned to the mean's orientation (segment shape sets it too), nothing more
    }
    // The surface itself: a rest body's edges come back with their lengths.
    const Sample s = sample(m, rng, m.component_count(), 0.0);
    const std::vector<Vector3d> again = laplacian.unpose(s.rest);
    const auto& tri = m.data().mesh.triangles;
    double stretch = 0;
    for (std::size_t t = 0; t < tri.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[t + k], b = tri[t + (k + 1) % 3];
            stretch += std::abs((again[a] - again[b]).norm() / (s.rest[a] - s.rest[b]).norm() - 1) / double(tri.size());
        }
    INFO("mean relative change of edge length " << stretch);
    CHECK(stretch < 0.02);
    // Bad input.
    std::vector<Vector3d> short_list(s.rest.begin(), s.rest.end() - 1);
    CHECK_THROWS_AS(laplacian.unpose(short_list), Error);
    std::vector<Vector3d> nan_body = s.rest;
    nan_body[7].x() = std::nan("");
    CHECK_THROWS_AS(laplacian.unpose(nan_body), Error);
    learning::LaplacianPostureOptions bad;
    bad.anchor = 0;
    CHECK_THROWS_AS(learning::LaplacianPosture(m, bad), Error);
    bad = {};
    bad.posture = std::nan("");
    CHECK_THROWS_AS(learning::LaplacianPosture(m, bad), Error);
    CHECK(learning::posture_from_name("laplacian") == learning::Posture::Laplacian);
    CHECK(std::string(learning::posture_name(learning::Posture::Laplacian)) == "laplacian");
}

TEST_CASE("a model learned from posed registrations: skeleton normalization keeps shape and drops posture", "[learning]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(11);
    constexpr uint32_t kShapes = 6, kTrain = 24, kTest = 6;
    std::vector<scan_files::RegisteredScan> train;
    std::vector<Sample> test;
    for (uint32_t i = 0; i < kTrain; ++i) train.push_back(sample(m, rng, kShapes, 0.6).scan);
    for (uint32_t i = 0; i < kTest; ++i) test.push_back(sample(m, rng, kShapes, 0.6));
    learning::LearnSpec spec;
    spec.components = 8;
    training::KnownAttribute age{"age", "years", "given", true, {}};
    for (uint32_t i = 0; i < kTrain; ++i) age.values.push_back(20 + i);
    spec.attributes = {age};
    learning::LearnReport report;
    const format::ModelData skeleton = learning::learn_model(m.data(), train, spec, &report);
    CHECK(report.bodies == kTrain);
    CHECK(report.components == 8);
    CHECK(report.explained > 0.999);  // six directions of shape explain it all
    spec.posture = learning::Posture::None;
    learning::LearnReport none_report;
    const format::ModelData none = learning::learn_model(m.data(), train, spec, &none_report);
    CHECK(none_report.explained < 0.99);  // posture needs more directions than eight
    // Held-out bodies at rest: the skeleton model represents them; the posture-laden one does not.
    const Model skeleton_model(skeleton, nullptr), none_model(none, nullptr);
    double skeleton_error = 0, none_error = 0;
    for (const Sample& s : test) {
        skeleton_error += simulation::best_approximation_error(skeleton_model, s.rest, true) / kTest;
        none_error += simulation::best_approximation_error(none_model, s.rest, true) / kTest;
    }
    INFO("held-out rest bodies: skeleton " << skeleton_error * 1e3 << " mm, none " << none_error * 1e3 << " mm");
    CHECK(skeleton_error < 0.5e-3);
    CHECK(none_error > 5 * skeleton_error);
    // The laplacian method needs no fits; its space holds shape and far less posture than none's.
    std::vector<scan_files::RegisteredScan> unfitted = train;
    for (auto& scan : unfitted) scan.has_fit = false, scan.fit = {};
    spec.posture = learning::Posture::Laplacian;
    learning::LearnReport laplacian_report;
    const format::ModelData laplacian = learning::learn_model(m.data(), unfitted, spec, &laplacian_report);
    const Model laplacian_model(laplacian, nullptr);
    double laplacian_error = 0;
    for (const Sample& s : test) laplacian_error += simulation::best_approximation_error(laplacian_model, s.rest, true) / kTest;
    INFO("explained by 8 components: skeleton " << report.explained << ", laplacian " << laplacian_report.explained << ", none " << none_report.explained
                                                << "; held-out rest bodies: laplacian " << laplacian_error * 1e3 << " mm");
    CHECK(laplacian_report.explained > none_report.explained);
    CHECK(laplacian_error < 0.5 * none_error);
    // Normalization runs on threads: the same bodies on one or two, and a body that fails is
    // reported from inside the pool.
    std::vector<scan_files::RegisteredScan> few(unfitted.begin(), unfitted.begin() + 4);
    const training::SampleMatrix one_thread = learning::normalized_bodies(m, few, learning::Posture::Laplacian, false, 1);
    const training::SampleMatrix two_threads = learning::normalized_bodies(m, few, learning::Posture::Laplacian, false, 2);
    CHECK(one_thread == two_threads);
    few[2].vertices[5].x() = std::nan("");
    CHECK_THROWS_AS(learning::normalized_bodies(m, few, learning::Posture::Laplacian, false, 2), Error);
    // The file round trip, the template's frame (feet on the ground), and the attributes.
    const std::vector<unsigned char> bytes = format::write_model(skeleton);
    ssc_model* loaded = nullptr;
    REQUIRE(ssc_model_load_memory(nullptr, bytes.data(), bytes.size(), &loaded) == SSC_OK);
    CHECK(ssc_model_shape_count(loaded) == 8);
    CHECK(ssc_model_vertex_count(loaded) == m.vertex_count());
    ssc_model_release(loaded);
    double lowest = 1e9, template_lowest = 1e9;
    for (uint32_t v = 0; v < m.vertex_count(); ++v) {
        lowest = std::min(lowest, double(skeleton.shape.mean[3 * std::size_t(v) + 1]));
        template_lowest = std::min(template_lowest, double(m.data().shape.mean[3 * std::size_t(v) + 1]));
    }
    INFO("lowest point of the mean: learned " << lowest << " m, template " << template_lowest << " m");
    CHECK(std::abs(lowest - template_lowest) < 0.02);
    const semantics::AttributeModel attributes(skeleton);
    CHECK(attributes.find("age") >= 0);
    CHECK(attributes.find("stature") >= 0);
    CHECK(skeleton.metadata.provenance.find("24 registrations") != std::string::npos);

    // A posture model (posture_fit.hpp): the registrations' fits are the default model's, learned
    // again onto the learned model as the template. With the posture model they unpose exactly as
    // before; read as the template's own fits (their first 8 values in its components) the joints
    // land elsewhere and the unposed bodies carry it.
    learning::LearnSpec posed_by = spec;
    posed_by.posture = learning::Posture::Skeleton;
    posed_by.attributes = {};
    posed_by.posture_model = std::make_shared<const format::ModelData>(m.data());
    const format::ModelData relearned = learning::learn_model(skeleton, train, posed_by);
    CHECK(relearned.metadata.provenance.find("with the poses of model '" + m.data().metadata.name + "'") != std::string::npos);
    std::vector<scan_files::RegisteredScan> misread = train;
    for (auto& scan : misread) scan.fit.shape.resize(8);
    learning::LearnSpec own = posed_by;
    own.posture_model = nullptr;
    const format::ModelData misread_model = learning::learn_model(skeleton, misread, own);
    const Model relearned_model(relearned, nullptr), misread_runtime(misread_model, nullptr);
    double relearned_error = 0, misread_error = 0;
    for (const Sample& s : test) {
        relearned_error += simulation::best_approximation_error(relearned_model, s.rest, true) / kTest;
        misread_error += simulation::best_approximation_error(misread_runtime, s.rest, true) / kTest;
    }
    INFO("held-out rest bodies, registrations unposed by the default model's fits: with it as the posture model " << relearned_error * 1e3
                                                                                                                 << " mm, read as the template's fits " << misread_error * 1e3 << " mm");
    CHECK(relearned_error < 0.5e-3);
    CHECK(misread_error > 20 * relearned_error);
}

TEST_CASE("evaluation: six shape directions generalize fully at six components, posture does not", "[learning]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(17);
    constexpr uint32_t kShapes = 6;
    std::vector<scan_files::RegisteredScan> scans;
    for (uint32_t i = 0; i < 16; ++i) scans.push_back(sample(m, rng, kShapes, 0.6).scan);
    learning::EvaluationSpec spec;
    spec.components = {1, 3, 6, 9};
    spec.samples = 200;
    spec.folds = 4;
    const auto skeleton = learning::evaluate_learning(learning::normalized_bodies(m, scans, learning::Posture::Skeleton), spec);
    const auto none = learning::evaluate_learning(learning::normalized_bodies(m, scans, learning::Posture::None), spec);
    REQUIRE(skeleton.size() == 4);
    REQUIRE(none.size() == 4);
    for (std::size_t k = 0; k < 4; ++k) {
        INFO("k " << skeleton[k].components << ": skeleton " << skeleton[k].compactness << " / " << skeleton[k].generalization * 1e3 << " mm / "
                  << skeleton[k].specificity * 1e3 << " mm; none " << none[k].compactness << " / " << none[k].generalization * 1e3 << " mm / "
                  << none[k].specificity * 1e3 << " mm");
        if (k > 0) {
            CHECK(skeleton[k].compactness >= skeleton[k - 1].compactness);
            CHECK(skeleton[k].generalization <= skeleton[k - 1].generalization + 1e-6);
        }
        CHECK(skeleton[k].compactness <= 1.0 + 1e-9);
        CHECK(skeleton[k].specificity > 0);
        CHECK(none[k].generalization > skeleton[k].generalization);
    }
    CHECK(skeleton[2].compactness > 0.999);      // six directions hold all the variance
    CHECK(skeleton[2].generalization < 0.5e-3);  // and reconstruct unseen bodies of them
    CHECK(none[2].generalization > 5e-3);        // posture needs more than six

    // A given model against the same bodies: the default model holds these shapes in its first
    // six components, so six reconstruct them.
    const auto given = learning::evaluate_model(m.data(), learning::normalized_bodies(m, scans, learning::Posture::Skeleton), spec);
    REQUIRE(given.size() == 4);
    CHECK(given[2].generalization < 0.5e-3);
    CHECK(given[0].generalization > 10 * given[2].generalization);
    CHECK_THROWS_WITH(learning::evaluate_learning(training::SampleMatrix(2, 3 * m.vertex_count()), spec), Catch::Contains("at least 3"));

    // Fewer training scans: 3 of the 16 held out, 13 to learn from; a size beyond them is left out.
    const training::SampleMatrix X = learning::normalized_bodies(m, scans, learning::Posture::Skeleton);
    const auto sized = learning::evaluate_training_sizes(X, {8, 4, 0, 500}, spec);
    REQUIRE(sized.size() == 3);
    CHECK(sized[0].size == 4);
    CHECK(sized[1].size == 8);
    CHECK(sized[2].size == 13);
    REQUIRE(sized[0].points.size() == 2);  // k = 1, 3: all that 4 bodies reach
    REQUIRE(sized[1].points.size() == 3);  // k = 1, 3, 6
    REQUIRE(sized[2].points.size() == 4);
    INFO("generalization at 3 components from 4 scans " << sized[0].points[1].generalization * 1e3 << " mm; at 6 from 8 scans "
                                                       << sized[1].points[2].generalization * 1e3 << " mm");
    CHECK(sized[1].points[2].generalization < 0.5e-3);  // 8 bodies span the six directions
    CHECK(sized[0].points[1].generalization > 10 * sized[1].points[2].generalization);
    CHECK_THROWS_WITH(learning::evaluate_training_sizes(X, {2}, spec), Catch::Contains("at least 3"));
    CHECK_THROWS_WITH(learning::evaluate_training_sizes(X.topRows(9), {5}, spec), Catch::Contains("at least 10"));
    spec.folds = 40;
    CHECK_THROWS_WITH(learning::evaluate_learning(learning::normalized_bodies(m, scans, learning::Posture::None), spec),
                      Catch::Contains("40 folds for 16 registrations"));
}

TEST_CASE("learning refuses bad registrations with a clear message", "[learning]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(3);
    std::vector<scan_files::RegisteredScan> scans;
    for (int i = 0; i < 4; ++i) scans.push_back(sample(m, rng, 4, 0.3).scan);
    learning::LearnSpec spec;
    spec.components = 3;
    auto refuses = [&](const std::vector<scan_files::RegisteredScan>& s, const learning::LearnSpec& sp, const std::string& words) {
        try {
            learning::learn_model(m.data(), s, sp);
            FAIL("accepted: " << words);
        } catch (const Error& e) {
            CHECK(e.status() == SSC_ERROR_INVALID_ARGUMENT);
            CHECK(std::string(e.what()).find(words) != std::string::npos);
        }
    };
    refuses({scans[0], scans[1]}, spec, "at least 3");
    learning::LearnSpec many = spec;
    many.components = 4;
    refuses(scans, many, "at most 3");
    auto broken = scans;
    broken[1].vertices.pop_back();
    refuses(broken, spec, "vertices");
    broken = scans;
    broken[2].vertices[7].x() = std::nan("");
    refuses(broken, spec, "not finite");
    broken = scans;
    broken[0].has_fit = false;
    refuses(broken, spec, "no model fit");
    learning::LearnSpec attrs = spec;
    attrs.attributes = {{"age", "years", "", true, {30, 40}}};
    refuses(scans, attrs, "2 values for 4");
    attrs.attributes = {{"age", "years", "", true, {30, 40, std::nan(""), 20}}};
    refuses(scans, attrs, "not finite");
    attrs.attributes = {{"age", "years", "", true, {30, 30, 30, 30}}};  // once "attributes.covariance has a diagonal entry <= 0"
    refuses(scans, attrs, "age is 30 for every registration");
    attrs.attributes = {{"age", "years", "", true, {30, 40, 1e300, 20}}};
    refuses(scans, attrs, "has the value 1e+300");
    attrs.attributes = {{"age", "years", "", true, {30, 40, 50, 20}}, {"age", "years", "", true, {1, 2, 3, 4}}};
    refuses(scans, attrs, "age is given twice");
    attrs.attributes.assign(65, {"a", "", "", true, {1, 2, 3, 4}});
    for (std::size_t a = 0; a < attrs.attributes.size(); ++a) attrs.attributes[a].name += std::to_string(a);
    refuses(scans, attrs, "65 attributes; at most 64");
    refuses({scans[0], scans[0], scans[0], scans[0]}, spec, "all the same body");
    learning::LearnSpec other_rig = spec;
    auto moved = std::make_shared<format::ModelData>(m.data());
    moved->skeleton.rest_orientations[4] += 0.2f;  // a joint's rest frame turned: its poses mean other rotations
    other_rig.posture_model = moved;
    refuses(scans, other_rig, "does not share the mesh, skeleton and skinning");
}

TEST_CASE("Procrustes with scale brings every body to one size and keeps their proportions", "[learning]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(23);
    std::vector<scan_files::RegisteredScan> scans;
    for (uint32_t i = 0; i < 12; ++i) scans.push_back(sample(m, rng, 10, 0.0).scan);
    auto sizes = [&](const training::SampleMatrix& X) {
        std::vector<double> out;
        for (Eigen::Index i = 0; i < X.rows(); ++i) {
            const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> b(X.row(i).data(), X.cols() / 3, 3);
            const Eigen::MatrixX3d d = b.cast<double>().rowwise() - b.cast<double>().colwise().mean();
            out.push_back(std::sqrt(d.squaredNorm() / double(b.rows())));
        }
        return out;
    };
    const std::vector<double> rigid = sizes(learning::normalized_bodies(m, scans, learning::Posture::None));
    const std::vector<double> scaled = sizes(learning::normalized_bodies(m, scans, learning::Posture::None, true));
    const auto [rlo, rhi] = std::minmax_element(rigid.begin(), rigid.end());
    const auto [slo, shi] = std::minmax_element(scaled.begin(), scaled.end());
    double average = 0;
    for (double s : rigid) average += s / double(rigid.size());
    INFO("body sizes (RMS radius): rigid " << *rlo << " to " << *rhi << " m, with scale " << *slo << " to " << *shi << " m");
    CHECK(*rhi - *rlo > 0.01);          // the collection's statures differ
    CHECK(*shi - *slo < 1e-3);          // one size with scale (within a millimetre) ...
    CHECK(std::abs(*slo - average) < 2e-3);  // ... the collection's average
    learning::LearnSpec spec;
    spec.components = 5;
    spec.posture = learning::Posture::None;
    learning::LearnReport rigid_report, scaled_report;
    learning::learn_model(m.data(), scans, spec, &rigid_report);
    spec.scale = true;
    const format::ModelData shapes = learning::learn_model(m.data(), scans, spec, &scaled_report);
    CHECK(scaled_report.total_variance < rigid_report.total_variance);  // size was part of the variance
    CHECK(shapes.metadata.provenance.find("with scale") != std::string::npos);
}

TEST_CASE("the template alone: a model without components loads, synthesizes its mean and is fitted in pose", "[learning]") {
    const Model& m = test::default_cpp_model();
    const format::ModelData alone = learning::template_only(m.data());
    CHECK(alone.component_count() == 0);
    CHECK(alone.metadata.name.find("template only") != std::string::npos);
    const std::vector<unsigned char> bytes = format::write_model(alone);
    test::ModelPtr model = test::load(bytes);
    REQUIRE(model);
    CHECK(ssc_model_shape_count(model.get()) == 0);
    CHECK(ssc_model_slider_count(model.get()) == 0);
    CHECK(ssc_model_sample_shapes(model.get(), 1, 3, 2.5f, nullptr, 0) == SSC_OK);  // three empty shapes
    // A posed template as the scan: the fit finds the pose (nothing else to find).
    std::mt19937 rng(31);
    const std::vector<float> pose = simulation::random_pose(m, rng, 0.2);
    const simulation::TrueBody truth = simulation::make_body(m, std::vector<float>(m.component_count(), 0.f), pose, Vector3d(0.1, 0, 0.2));
    std::vector<float> points;
    for (const auto& v : truth.vertices)
        for (int a = 0; a < 3; ++a) points.push_back(float(v[a]));
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(model.get(), nullptr, &fitter) == SSC_OK);
    REQUIRE(ssc_fitter_add_points(fitter, 0, points.data(), nullptr, nullptr, uint32_t(truth.vertices.size()), 0) == SSC_OK);
    ssc_fit_report report{};
    report.struct_size = sizeof report;
    CHECK(ssc_fitter_solve(fitter, nullptr, nullptr, &report) == SSC_OK);
    std::vector<float> fitted(points.size());
    REQUIRE(ssc_fitter_get_vertices(fitter, 0, fitted.data(), uint32_t(truth.vertices.size()), 0) == SSC_OK);
    double error = 0;
    for (std::size_t v = 0; v < truth.vertices.size(); ++v)
        error += (Vector3d(fitted[3 * v], fitted[3 * v + 1], fitted[3 * v + 2]) - truth.vertices[v]).norm() / double(truth.vertices.size());
    INFO("mean vertex error " << error * 1e3 << " mm after " << report.iterations << " iterations");
    CHECK(error < 0.005);
    ssc_fitter_destroy(fitter);
}
