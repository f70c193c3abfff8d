#include "train.hpp"

#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"
#include "common/error.hpp"
#include "landmarks.hpp"
#include "render/landmark_picture.hpp"
#include "measure/girth.hpp"
#include "measure/measurements.hpp"
#include "render/raster.hpp"
#include "pca.hpp"
#include "skeleton_fit.hpp"

#include <algorithm>
#include <map>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ssc::training {
namespace {

// Vertex sets (body parts) by each vertex's dominant game bone: its joint role's part.
std::string part_of(const format::ModelData& m, uint16_t joint) {
    return anatomy::part_name(anatomy::BodyPart(m.joint_roles[joint].part));
}

}  // namespace

format::ModelData train_model(const TrainSpec& spec, TrainReport& report, const Progress& progress) {
    auto tick = [&](const std::string& stage, uint32_t done, uint32_t total) {
        if (progress && !progress(stage, done, total)) fail(SSC_ERROR_CANCELLED, "training cancelled");
    };
    auto say = [&](const std::string& stage) { tick(stage, 0, 0); };
    SSC_REQUIRE_ARG(spec.components >= 1, "components must be at least 1");
    SSC_REQUIRE_ARG(spec.population.count > spec.heldout + spec.components, "population too small for the components and held-out bodies");
    SSC_REQUIRE_ARG(spec.population.count > spec.heldout + spec.segment_components, "population too small for the segment components and held-out bodies");
    SSC_REQUIRE_ARG(spec.segment_components == 0 || (spec.segment_band >= 0.005 && spec.segment_band <= 0.5),
                    "the segments' blend band must lie in [0.005, 0.5] m");
    say("loading assets from " + spec.assets_root);
    const mh::Assets a = mh::load_assets(spec.assets_root);

    say("sampling " + std::to_string(spec.population.count) + " bodies (stature calibrated per body)");
    const std::vector<BodyParams> people =
        sample_population(a, spec.population, {}, [&](uint32_t done, uint32_t total) { tick("sampling bodies", done, total); return true; });
    if (!spec.population_csv.empty()) write_population_csv(spec.population_csv, a, people);

    const uint32_t N = spec.population.count, V = mh::kBodyVertices, J = uint32_t(a.game_rig.bones.size());
    SampleMatrix X(N, 3 * V), joints(N, 3 * J);
    std::vector<float> xyz;
    report.statures.clear();
    report.bmi.clear();
    report.male.clear();
    say("generating bodies");
    for (uint32_t i = 0; i < N; ++i) {
        tick("generating bodies", i, N);
        mh::generate_body(a, people[i].macro, people[i].modifiers, xyz);
        // Stand every body on the ground (y = 0) centred over the origin in x and z, so the
        // model keeps the feet on the floor instead of learning where the asset put them.
        double cx = 0, cz = 0;
        float lo = 1e30f;
        for (uint32_t v = 0; v < V; ++v) {
            cx += xyz[3 * v];
            cz += xyz[3 * v + 2];
            lo = std::min(lo, xyz[3 * v + 1]);
        }
        const float shift[3] = {float(-cx / V), -lo, float(-cz / V)};
        for (std::size_t k = 0; k < xyz.size(); ++k) xyz[k] += shift[k % 3];
        std::copy(xyz.begin(), xyz.begin() + 3 * V, X.row(i).data());
        const std::vector<float> jp = game_joint_positions(a, xyz);
        std::copy(jp.begin(), jp.end(), joints.row(i).data());
        report.statures.push_back(stature(xyz));
        report.bmi.push_back(body_volume(a, xyz) * kBodyDensity / (report.statures.back() * report.statures.back()));
        report.male.push_back(people[i].male);
    }
    if (spec.procrustes) procrustes_align(X);

    say("learning the joint regressor");
    const Regressor reg = learn_regressor(X, joints, spec.regressor_support, spec.heldout);
    report.regressor_mean_error = reg.heldout_mean_error;
    report.regressor_max_error = reg.heldout_max_error;
    report.joint_errors.clear();
    for (uint32_t j = 0; j < J; ++j) report.joint_errors.emplace_back(a.game_rig.bones[j].name, reg.joint_mean_error[j]);

    // The held-out bodies stay out of the PCA too: they measure generalization.
    const uint32_t fit = N - spec.heldout;
    say("PCA of " + std::to_string(fit) + " bodies x " + std::to_string(3 * V) + " coordinates");
    const Pca p = pca(X, fit, spec.components, spec.population.seed);
    report.bodies = fit;
    report.total_variance = p.total_variance;
    report.stddev.assign(p.stddev.data(), p.stddev.data() + p.stddev.size());
    const uint32_t K = uint32_t(p.basis.cols());
    if (spec.heldout > 0) {
        say("measuring compactness, generalization and specificity");
        std::vector<uint32_t> ks;
        for (uint32_t k : {1u, 2u, 3u, 5u, 10u, 15u, 20u, 30u, 40u, 50u, 75u, 100u})
            if (k <= K) ks.push_back(k);
        if (ks.empty() || ks.back() != K) ks.push_back(K);
        const SampleMatrix training = X.topRows(fit), heldout = X.bottomRows(spec.heldout);
        report.quality = evaluate_quality(p, training, heldout, ks, spec.specificity_samples, spec.population.seed + 1);
        if (!spec.report_prefix.empty()) report.plots = write_quality_report(spec.report_prefix, report.quality);
    }

    format::ModelData m;
    m.metadata.name = "sscape-default";
    m.metadata.model_version = "0.1";
    m.metadata.license = "CC0-1.0 (trained from the CC0 MakeHuman assets)";
    std::ostringstream prov;
    prov << "Trained by sscape train from the CC0 MakeHuman assets:\n" << a.manifest << "population: " << N
         << " bodies, seed " << spec.population.seed << ", ages " << spec.population.min_age << "-" << spec.population.max_age
         << ", modifier sd " << spec.population.modifier_sd << "; " << K << " components";
    m.metadata.provenance = prov.str();
    m.metadata.description = "Adult body shape space (S-SCAPE) with the 53-bone game-engine skeleton.";

    m.mesh.vertex_count = V;
    for (std::size_t q = 0; q < a.base.body_quads.size(); q += 4) {
        const uint32_t* c = &a.base.body_quads[q];
        const uint32_t* t = &a.base.body_quad_uvs[q];
        for (int k = 0; k < 4; ++k) {
            m.mesh.quads.push_back(c[k]);
            m.mesh.quad_uvs.push_back(t[k]);
        }
        for (int k : {0, 1, 2, 0, 2, 3}) {
            m.mesh.triangles.push_back(c[k]);
            m.mesh.triangle_uvs.push_back(t[k]);
        }
    }
    m.mesh.uvs.assign(a.base.uvs.begin(), a.base.uvs.end());

    m.shape.mean.assign(p.mean.data(), p.mean.data() + p.mean.size());
    m.shape.stddev.resize(K);
    std::vector<float> scaled(std::size_t(K) * 3 * V);  // planar, metres per SD
    for (uint32_t k = 0; k < K; ++k) {
        m.shape.stddev[k] = float(p.stddev(k));
        for (uint32_t v = 0; v < V; ++v)
            for (int c = 0; c < 3; ++c) scaled[std::size_t(k) * 3 * V + std::size_t(c) * V + v] = float(p.stddev(k)) * p.basis(3 * v + c, k);
    }
    say("quantizing the basis");
    m.shape.basis = format::quantize_basis(scaled.data(), V, K, spec.tolerance, &report.quantization);

    auto& sk = m.skeleton;
    std::vector<float> mean_body(a.base.xyz);
    mh::generate_body(a, mh::MacroSliders{}, {}, mean_body);
    const std::vector<float> rest = game_rest_orientations(a, mean_body);
    for (uint32_t j = 0; j < J; ++j) {
        const auto& b = a.game_rig.bones[j];
        sk.joint_names.push_back(b.name);
        int parent = -1;
        for (uint32_t q = 0; q < j; ++q)
            if (a.game_rig.bones[q].name == b.parent) parent = int(q);
        sk.parents.push_back(parent);
    }
    sk.rest_orientations.assign(rest.begin(), rest.end());
    sk.regressor_offsets.assign(reg.offsets.begin(), reg.offsets.end());
    sk.regressor_vertices.assign(reg.vertices.begin(), reg.vertices.end());
    sk.regressor_weights.assign(reg.weights.begin(), reg.weights.end());
    m.joint_limits = anatomy::compute_joint_limits(sk);
    m.joint_roles = anatomy::compute_joint_roles(sk);

    std::vector<uint16_t> sj;
    std::vector<float> sw;
    game_skin_weights(a, sj, sw);
    m.skin.joints.assign(sj.begin(), sj.end());
    m.skin.weights.assign(sw.begin(), sw.end());

    std::map<std::string, std::vector<uint32_t>> parts;
    for (uint32_t v = 0; v < V; ++v) parts[part_of(m, sj[4 * v])].push_back(v);
    for (const char* name : {"head", "torso", "arms", "hands", "legs", "feet"}) {
        format::VertexSet set;
        set.name = name;
        set.vertices.assign(parts[name].begin(), parts[name].end());
        if (!set.vertices.empty()) m.vertex_sets.push_back(std::move(set));
    }
    say("placing the 73 CAESAR landmarks");
    const LandmarkTemplate lt = landmark_template(m, p.mean.data());
    m.landmarks = place_caesar_landmarks(lt);
    if (!spec.levels.proxies.empty() || spec.levels.simplified_vertices > 0) {
        say("levels of detail: the template simplified, the proxy meshes bound");
        m.levels = make_detail_levels(a, m, mean_body, spec.levels, &report.levels);
    }
    format::validate_model(m);

    say("measuring every training body for the attribute model (sliders, made to measure)");
    m.attributes = learn_attribute_model(m, X, p, fit, population_attributes(people));
    report.segments.clear();
    if (spec.segment_components > 0) {
        say("PCA per body segment");
        SegmentSpec segments;
        segments.components = spec.segment_components;
        segments.band = spec.segment_band;
        segments.tolerance = spec.tolerance;
        segments.seed = spec.population.seed;
        m.segments = learn_segments(m, X, fit, p, segments, &report.segments);
        m.metadata.provenance += "\nsegment shape spaces: " + std::to_string(spec.segment_components) + " components each, blend band " +
                                 std::to_string(int(std::lround(spec.segment_band * 1000))) + " mm";
        format::validate_model(m);
    }
    const uint32_t mtm = std::min(spec.made_to_measure_bodies, spec.heldout);
    if (mtm > 0) {
        say("making " + std::to_string(mtm) + " held-out bodies to measure");
        report.made_to_measure = evaluate_made_to_measure(m, X, fit, mtm, people);
        if (!spec.report_prefix.empty()) {
            const std::string csv = spec.report_prefix + "made_to_measure.csv";
            std::ofstream f(csv);
            const auto& r = report.made_to_measure;
            f << "# made to measure: " << r.bodies << " held-out bodies, stature/chest/waist/hip requested with sex and age; "
              << r.converged << " converged\nmeasurement,mean_error_m,worst_error_m,regression_start_mean_error_m\n";
            for (std::size_t k = 0; k < r.measurements.size(); ++k)
                f << r.measurements[k] << "," << r.mean_error[k] << "," << r.worst_error[k] << "," << r.start_mean_error[k] << "\n";
            if (!f) fail(SSC_ERROR_IO, "cannot write " + csv);
        }
    }

    say("measuring girths of every body");
    {
        std::vector<uint8_t> torso(V, 0), trunk_legs(V, 0);
        for (uint32_t v = 0; v < V; ++v) {
            const std::string part = part_of(m, sj[4 * v]);
            torso[v] = part == "torso";
            trunk_legs[v] = part == "torso" || part == "legs";
        }
        auto landmark_y = [&](const float* body, const std::string& name) {
            for (uint32_t l = 0; l < m.landmarks.size(); ++l)
                if (m.landmarks[l].name == name) return measure::landmark_position(m, l, body).y();
            fail(SSC_ERROR_INTERNAL, "no landmark " + name);
        };
        const std::size_t T = m.mesh.triangles.size() / 3;
        const std::vector<uint32_t> torso_edges = measure::mesh_edges(m.mesh.triangles.data(), T, torso),
                                    trunk_legs_edges = measure::mesh_edges(m.mesh.triangles.data(), T, trunk_legs);
        auto girth_at = [](const float* xyz, const std::vector<uint32_t>& edges, double y) {
            return measure::tape_girth(measure::plane_section(xyz, edges, measure::horizontal_plane(y)), measure::horizontal_plane(y));
        };
        std::vector<float> body(3ull * V);
        report.chest.clear();
        report.waist_iliac.clear();
        report.waist_natural.clear();
        report.hip.clear();
        for (uint32_t b = 0; b < N; ++b) {
            for (std::size_t k = 0; k < body.size(); ++k) body[k] = X(b, Eigen::Index(k)) + (b < fit ? p.mean(Eigen::Index(k)) : 0.f);
            const double bust = 0.5 * (landmark_y(body.data(), "Rt. Thelion/Bustpoint") + landmark_y(body.data(), "Lt. Thelion/Bustpoint"));
            const double crest = 0.5 * (landmark_y(body.data(), "Rt. Iliocristale") + landmark_y(body.data(), "Lt. Iliocristale"));
            const double troch = 0.5 * (landmark_y(body.data(), "Rt. Trochanterion") + landmark_y(body.data(), "Lt. Trochanterion"));
            report.chest.push_back(girth_at(body.data(), torso_edges, bust));
            report.waist_iliac.push_back(girth_at(body.data(), torso_edges, crest));
            report.waist_natural.push_back(girth_at(body.data(), torso_edges, landmark_y(body.data(), "Waist, Preferred, Post.")));
            double hip = 0;
            for (double y = troch - 0.06; y <= troch + 0.06; y += 0.005) hip = std::max(hip, girth_at(body.data(), trunk_legs_edges, y));
            report.hip.push_back(hip);
        }
    }
    if (!spec.report_prefix.empty()) {
        const std::string png = spec.report_prefix + "landmarks.png";
        std::vector<float> at;
        for (const auto& l : m.landmarks) {
            const Eigen::Vector3d p = landmark_position(l, lt.xyz.data(), lt.triangles.data());
            at.insert(at.end(), {float(p.x()), float(p.y()), float(p.z())});
        }
        render::write_landmark_picture(png, lt.xyz, lt.triangles, at);
        report.plots.push_back(png);
    }
    format::validate_model(m);
    return m;
}

}  // namespace ssc::training
