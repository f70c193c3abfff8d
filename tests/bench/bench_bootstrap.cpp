// The end-to-end benchmark of learning from scans (issue 23), on ground truth that is CC0 only:
// MakeHuman bodies (with modifiers the default model was not trained on) standing in a booth
// scanner's pose with people's variation (simulation::scanning_pose), scanned by the simulated booth
// (noise, unseen parts), then bootstrapped from a deliberately weak start (a model learned from 50
// other true bodies with 5 components). Measures per round the accepted scans and the
// registrations' error against the true meshes; then the final model's generalization on held-out
// true bodies beside a model learned directly from the true rest meshes, and the posture
// normalizations none, skeleton and laplacian (also from the true posed meshes), with pictures of their first five components at +-3 SD.
//
// The collection comes from testing::simulate_collection.
//
// usage: sscape_bootstrap_bench --makehuman DIR [--scans 200] [--heldout 50] [--rounds 3]
//                               [--components 20] [--points 30000] [--out DIR] [--threads N] [--start weak|template|default]
//                               [--segment-components K] [--no-fit-segments] [--landmarks SD] [--posture-model builtin|own]
// --start default: the built-in model (which has segment shape spaces); --segment-components: the
// rounds' models learn them too; every round registers with them in the model fit where its model
// has them (--no-fit-segments: the whole body's components only). --landmarks SD: each scan comes
// with its CAESAR landmarks (but the hands'), placed with SD metres of error per axis.
// --posture-model: the skeleton normalization unposes with the built-in model's fits to the scans
// (the default, as sscape bootstrap's) or with each round's own fits.
#include "paths.hpp"

#include "common/files.hpp"
#include "common/rigid.hpp"
#include "common/thread_pool.hpp"
#include "fitting/nearest.hpp"
#include "learning/bootstrap.hpp"
#include "learning/evaluate_learning.hpp"
#include "learning/posture_fit.hpp"
#include "scan_files/registration_record.hpp"
#include "testing/simulated_collection.hpp"
#include "registration/registration_quality.hpp"
#include "render/raster.hpp"
#include "render/text.hpp"
#include "simulation/simulate.hpp"
#include "sscape_format/model_io.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

using namespace ssc;
using Eigen::Vector3d;
namespace fs = std::filesystem;

namespace {

std::vector<unsigned char> file_bytes(const std::string& path) {
    const std::string s = read_regular_file(path, 1ull << 30);
    return std::vector<unsigned char>(s.begin(), s.end());
}

training::SampleMatrix rows_of(const std::vector<std::vector<Vector3d>>& bodies) {
    training::SampleMatrix X(Eigen::Index(bodies.size()), 3 * Eigen::Index(bodies.at(0).size()));
    for (std::size_t i = 0; i < bodies.size(); ++i)
        for (std::size_t v = 0; v < bodies[i].size(); ++v)
            for (int a = 0; a < 3; ++a) X(Eigen::Index(i), Eigen::Index(3 * v) + a) = float(bodies[i][v][a]);
    return X;
}

// The first five components at -3 and +3 SD (rows), front and side, one picture per model.
void component_picture(const std::string& path, const format::ModelData& data, const std::string& title) {
    const Model m(data, nullptr);
    const uint32_t V = m.vertex_count(), K = std::min<uint32_t>(5, m.component_count());
    const fitting::LinearModel lin(m, m.component_count());
    const int cell_w = 150, cell_h = 300, header = 30;
    render::Image img(int(2 * K) * cell_w, header + 2 * cell_h);
    const uint8_t ink[3] = {40, 40, 40}, skin[3] = {225, 190, 160};
    render::draw_text(img, 8, 8, title + ": components 1-5 (front, side) at -3 SD (top) and +3 SD (bottom)", 2, ink);
    const auto& tris = data.mesh.triangles;
    for (uint32_t k = 0; k < K; ++k)
        for (int row = 0; row < 2; ++row) {
            std::vector<float> xyz(3 * std::size_t(V));
            for (uint32_t v = 0; v < V; ++v)
                for (int a = 0; a < 3; ++a)
                    xyz[3 * v + a] = data.shape.mean[3 * v + a] + float((row ? 3 : -3) * lin.basis[(3 * v + a) * lin.K + k] * lin.step[k]);
            float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
            for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
            for (int view = 0; view < 2; ++view) {
                std::vector<float> depth;
                render::Viewport vp{int(2 * k + view) * cell_w, header + row * cell_h, cell_w, cell_h,
                                    view == 0 ? 0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]), 0.5f * (lo[1] + hi[1]), 0.9f * cell_h / 2.0f};
                render::draw_mesh(img, depth, vp, view == 0 ? render::View::Front : render::View::Side, xyz.data(), tris.data(),
                                  uint32_t(tris.size() / 3), skin);
            }
        }
    render::write_png(path, img);
}

// Joint j's rotation in a pose stored as xyzw per joint (the simulator's and the format's order).
Eigen::Quaterniond joint_rotation(const std::vector<float>& pose, uint32_t j) {
    return Eigen::Quaterniond(pose[4 * j + 3], pose[4 * j], pose[4 * j + 1], pose[4 * j + 2]);
}

// Generalization that counts how far the surfaces lie apart, not where a vertex lies along them:
// each held-out body (rigidly on the model's mean) reconstructed from k components whose vertices
// are drawn to the body's surface (point to plane at the nearest vertex, five rounds), then the
// mean of both directions' point-to-plane distances (m), per k. Registrations slide the template
// along the body against the truth's vertex layout (docs/registration.md, "Why the fit slides");
// the plain generalization charges a model learned from them for that, this one does not.
std::vector<double> surface_generalization(const format::ModelData& data, const std::vector<std::vector<Vector3d>>& bodies, const std::vector<uint32_t>& ks,
                                           ThreadPool& pool) {
    const Model m(data, nullptr);
    const uint32_t V = m.vertex_count(), K = m.component_count();
    const Eigen::Index D = 3 * Eigen::Index(V);
    const fitting::LinearModel lin(m, K);
    Eigen::MatrixXd B(D, K);
    for (Eigen::Index r = 0; r < D; ++r)
        for (uint32_t k = 0; k < K; ++k) B(r, k) = lin.basis[std::size_t(r) * K + k] * lin.step[k];
    const Eigen::Map<const Eigen::VectorXf> mean_f(data.shape.mean.data(), D);
    const Eigen::VectorXd mean = mean_f.cast<double>();
    Eigen::Matrix3Xd mean_points(3, V);
    for (uint32_t v = 0; v < V; ++v) mean_points.col(v) = mean.segment<3>(3 * v);
    const std::vector<uint32_t> tri(data.mesh.triangles.begin(), data.mesh.triangles.end());
    std::vector<double> out;
    for (uint32_t k : ks) {
        if (k > K) {
            out.push_back(-1);
            continue;
        }
        const Eigen::MatrixXd Bk = B.leftCols(k);
        const Eigen::LDLT<Eigen::MatrixXd> normal_matrix((Bk.transpose() * Bk).eval());
        std::vector<double> error(bodies.size());
        pool.parallel_for(bodies.size(), [&](std::size_t i, unsigned) {
            Eigen::Matrix3Xd h(3, V);
            for (uint32_t v = 0; v < V; ++v) h.col(v) = bodies[i][v];
            const Similarity T = align_points(h, mean_points, false);
            std::vector<Vector3d> body(V);
            for (uint32_t v = 0; v < V; ++v) body[v] = T.R * h.col(v) + T.t;
            const std::vector<Vector3d> body_n = registration::vertex_normals(body, tri);
            const fitting::PointIndex body_index(body);
            Eigen::VectorXd y(D);
            for (uint32_t v = 0; v < V; ++v) y.segment<3>(3 * v) = body[v];
            Eigen::VectorXd c = normal_matrix.solve(Bk.transpose() * (y - mean));
            for (int round = 0; round < 5; ++round) {
                const Eigen::VectorXd x = mean + Bk * c;
                for (uint32_t v = 0; v < V; ++v) {
                    const Vector3d p = x.segment<3>(3 * v);
                    const uint32_t t = body_index.nearest(p, nullptr);
                    y.segment<3>(3 * v) = p - body_n[t] * body_n[t].dot(p - body[t]);
                }
                c = normal_matrix.solve(Bk.transpose() * (y - mean));
            }
            const Eigen::VectorXd x = mean + Bk * c;
            std::vector<Vector3d> rec(V);
            for (uint32_t v = 0; v < V; ++v) rec[v] = x.segment<3>(3 * v);
            const std::vector<Vector3d> rec_n = registration::vertex_normals(rec, tri);
            const fitting::PointIndex rec_index(rec);
            double there = 0, back = 0;
            for (uint32_t v = 0; v < V; ++v) {
                const uint32_t t = body_index.nearest(rec[v], nullptr);
                there += std::abs(body_n[t].dot(rec[v] - body[t])) / V;
                const uint32_t r = rec_index.nearest(body[v], nullptr);
                back += std::abs(rec_n[r].dot(body[v] - rec[r])) / V;
            }
            error[i] = (there + back) / 2;
        });
        double sum = 0;
        for (double e : error) sum += e;
        out.push_back(sum / double(bodies.size()));
    }
    return out;
}

// The fitted pose's error against the pose the truth was given: the mean rotation angle over the
// joints `moved` marks (the spine's, clavicles', limbs' and head's), and over every joint (degrees).
std::pair<double, double> pose_error_degrees(const std::vector<uint8_t>& moved, const fitting::FitState& fit, const std::vector<float>& true_pose) {
    double limbs = 0, every = 0;
    int n_limbs = 0;
    const uint32_t J = uint32_t(moved.size());
    for (uint32_t j = 0; j < J; ++j) {
        const double angle = Eigen::AngleAxisd(fit.pose[j].normalized() * joint_rotation(true_pose, j).normalized().conjugate()).angle() * 180 / M_PI;
        every += angle / J;
        if (moved[j]) limbs += angle, ++n_limbs;
    }
    return {limbs / std::max(1, n_limbs), every};
}

// How far a learned model's mean lies from the true rest meshes' model's mean (both in the
// template's frame; their mean offset taken off), per vertex, over the body and per region.
void print_mean_offset(const char* name, const format::ModelData& learned, const format::ModelData& truth) {
    const uint32_t V = truth.vertex_count();
    auto diff = [&](uint32_t v) {
        return Vector3d((Eigen::Map<const Eigen::Vector3f>(&learned.shape.mean[3 * std::size_t(v)]) - Eigen::Map<const Eigen::Vector3f>(&truth.shape.mean[3 * std::size_t(v)])).cast<double>());
    };
    Vector3d shift = Vector3d::Zero();
    for (uint32_t v = 0; v < V; ++v) shift += diff(v) / V;
    double all = 0;
    for (uint32_t v = 0; v < V; ++v) all += (diff(v) - shift).norm() / V;
    std::printf("%-38s %5.2f mm", name, 1e3 * all);
    for (const auto& set : truth.vertex_sets) {
        double r = 0;
        for (uint32_t v : set.vertices) r += (diff(v) - shift).norm() / double(set.vertices.size());
        std::printf("   %s %.2f", set.name.c_str(), 1e3 * r);
    }
    std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
    std::string makehuman, out = "bootstrap_bench", start = "weak";
    uint32_t scans = 200, heldout = 50, rounds = 3, components = 20, points = 30000, threads = 0, segment_components = 0;
    bool fit_segments = true;
    double landmark_noise = -1;
    std::string posture = "skeleton", posture_model = "builtin";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
        if (a == "--makehuman") makehuman = next();
        else if (a == "--scans") scans = uint32_t(std::stoul(next()));
        else if (a == "--heldout") heldout = uint32_t(std::stoul(next()));
        else if (a == "--rounds") rounds = uint32_t(std::stoul(next()));
        else if (a == "--components") components = uint32_t(std::stoul(next()));
        else if (a == "--points") points = uint32_t(std::stoul(next()));
        else if (a == "--threads") threads = uint32_t(std::stoul(next()));
        else if (a == "--out") out = next();
        else if (a == "--start") start = next();
        else if (a == "--segment-components") segment_components = uint32_t(std::stoul(next()));
        else if (a == "--fit-segments") fit_segments = true;  // the default
        else if (a == "--no-fit-segments") fit_segments = false;
        else if (a == "--landmarks") landmark_noise = std::stod(next());
        else if (a == "--posture") posture = next();
        else if (a == "--posture-model") posture_model = next();
        else {
            std::fprintf(stderr, "usage: sscape_bootstrap_bench --makehuman DIR [--scans N] [--heldout N] [--rounds N] [--components K] [--points N] [--out DIR] [--threads N] "
                                 "[--start weak|template|default] [--segment-components K] [--no-fit-segments] [--landmarks SD] [--posture none|skeleton|laplacian] [--posture-model builtin|own]\n");
            return 2;
        }
    }
    if (makehuman.empty() || scans < 10 || (start != "weak" && start != "template" && start != "default") ||
        (posture_model != "builtin" && posture_model != "own")) {
        std::fprintf(stderr, "sscape_bootstrap_bench: --makehuman DIR is required (../shared/makehuman), and at least 10 scans\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto now = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    const format::ModelData default_data = format::read_model_file(sscape_paths::default_model_file());
    const Model model(default_data, nullptr);
    const uint32_t V = model.vertex_count();

    // The people: scanned ones (booth scans and truth), held-out ones and the weak start's 50 (rest only).
    testing::CollectionSpec cs;
    cs.scans = scans;
    cs.extra = heldout + 50;
    cs.points = points;
    cs.landmark_noise = landmark_noise;
    const testing::SimulatedCollection collection = testing::simulate_collection(makehuman, model, cs, out + "/scans");
    const auto& rest = collection.rest;
    const auto& truth = collection.truth;
    const auto& true_pose = collection.poses;
    learning::BootstrapSpec spec;
    spec.scans = collection.scans;
    std::printf("[%5.0f s] %u booth scans of %u points in %s/scans (MakeHuman bodies beyond the model), %u more people held out, 50 for the weak start\n",
                now(), scans, points, out.c_str(), heldout);

    // The weak start: 5 components learned from 50 other true bodies at rest.
    std::vector<scan_files::RegisteredScan> weak_bodies;
    for (std::size_t p = scans + heldout; p < rest.size(); ++p) weak_bodies.push_back({"weak", rest[p], false, {}});
    learning::LearnSpec weak_spec;
    weak_spec.components = 5;
    weak_spec.posture = learning::Posture::None;
    weak_spec.name = "weak-start";
    // Or weaker still: the template alone (--start template); or the built-in model (--start default).
    const std::vector<unsigned char> weak = format::write_model(start == "template" ? learning::template_only(default_data)
                                                                : start == "default" ? default_data
                                                                                     : learning::learn_model(default_data, weak_bodies, weak_spec));

    // Bootstrapping.
    spec.out_dir = out + "/boot";
    spec.rounds = rounds;
    spec.threads = threads;
    spec.learn.components = components;
    spec.learn.segment_components = segment_components;
    spec.learn.posture = learning::posture_from_name(posture);
    spec.registration.segments = fit_segments;
    if (posture_model == "builtin") spec.posture_model = format::write_model(default_data);
    spec.sheet_entries = 12;
    const std::vector<learning::RoundReport> reports = learning::bootstrap(weak, spec, [&](const std::string& line) {
        if (line.find(" of ") == std::string::npos || line.find("learning") != std::string::npos) std::printf("[%5.0f s] %s\n", now(), line.c_str());
        std::fflush(stdout);
        return true;
    });

    // Each round's registrations against the truth (correspondence: vertex i on true vertex i).
    std::vector<uint8_t> hand(V, 0);
    for (const auto& set : default_data.vertex_sets)
        if (set.name == "hands")
            for (uint32_t v : set.vertices) hand[v] = 1;
    std::vector<uint8_t> moved(model.joint_count(), 0);  // the joints whose pose error is reported apart
    for (const char* name : {"spine_01", "spine_02", "spine_03", "clavicle_l", "clavicle_r", "upperarm_l", "upperarm_r", "lowerarm_l", "lowerarm_r", "head",
                             "thigh_l", "thigh_r", "calf_l", "calf_r"})
        if (const int64_t j = model.find_joint(name); j >= 0) moved[std::size_t(j)] = 1;
    std::printf("\nround  accepted  rejected  failed  error all (mm)  accepted (mm)  without hands (mm)  registering s/scan  pose error: limbs, all (deg)\n");
    std::vector<scan_files::RegisteredScan> last_accepted, last_true_pose;  // the latter unposed with the pose the truth was given
    std::vector<scan_files::RegisteredScan> last_posture_fitted;            // with the posture model's fits (--posture-model builtin)
    double posture_limbs = 0, posture_all = 0;
    std::unique_ptr<const learning::PostureModel> posture_fitter;
    if (!spec.posture_model.empty()) posture_fitter = std::make_unique<const learning::PostureModel>(spec.posture_model, spec.registration);
    for (const auto& r : reports) {
        const std::string dir = spec.out_dir + "/round_" + std::to_string(r.round);
        const std::vector<unsigned char> bytes = file_bytes(spec.out_dir + "/round_" + std::to_string(r.round - 1) + "/model.sscape");
        const Model used(format::read_model(bytes.data(), bytes.size()), nullptr);
        std::FILE* dec = std::fopen((dir + "/decisions.csv").c_str(), "r");
        char line[4096];
        std::vector<std::string> accepted_names;
        while (dec && std::fgets(line, sizeof line, dec))
            if (std::strstr(line, ",accept,")) accepted_names.push_back(std::string(line, std::strchr(line, ',') - line));
        if (dec) std::fclose(dec);
        double all = 0, acc = 0, body = 0, pose_limbs = 0, pose_all = 0;
        std::size_t n_all = 0, n_acc = 0;
        if (r.round == reports.back().round) last_accepted.clear();
        for (uint32_t s = 0; s < scans; ++s) {
            const std::string mesh = dir + "/registrations/" + spec.scans[s].name + ".ply";
            if (!fs::exists(scan_files::record_report_path(mesh))) continue;
            const scan_files::RegistrationRecord rec = scan_files::read_registration_record(mesh, used, true);
            double e = 0, eb = 0;
            std::size_t nb = 0;
            for (uint32_t v = 0; v < V; ++v) {
                const double d = (rec.registered.vertices[v] - truth[s][v]).norm();
                e += d / V;
                if (!hand[v]) eb += d, ++nb;
            }
            all += e, ++n_all;
            const auto pose_error = pose_error_degrees(moved, rec.registered.fit, true_pose[s]);
            pose_limbs += pose_error.first, pose_all += pose_error.second;
            if (std::find(accepted_names.begin(), accepted_names.end(), spec.scans[s].name) != accepted_names.end()) {
                acc += e, body += eb / double(nb), ++n_acc;
                if (r.round == reports.back().round) {
                    last_accepted.push_back(rec.registered);
                    scan_files::RegisteredScan known = rec.registered;
                    for (uint32_t j = 0; j < model.joint_count(); ++j)
                        known.fit.pose[j] = joint_rotation(true_pose[s], j);
                    last_true_pose.push_back(known);
                    if (posture_fitter) {  // the posture fit the bootstrap made (found on disk)
                        scan_files::RegisteredScan posed_by = rec.registered;
                        posed_by.fit = posture_fitter->fit(spec.scans[s], spec.reading, learning::posture_fit_path(spec.out_dir, spec.scans[s].name));
                        const auto e = pose_error_degrees(moved, posed_by.fit, true_pose[s]);
                        posture_limbs += e.first, posture_all += e.second;
                        last_posture_fitted.push_back(posed_by);
                    }
                }
            }
        }
        std::printf("%5u  %8zu  %8zu  %6zu  %14.2f  %13.2f  %18.2f  %18.2f  %13.2f %12.2f\n", r.round, r.accepted, r.rejected, r.failed, 1e3 * all / double(n_all),
                    1e3 * acc / double(std::max<std::size_t>(1, n_acc)), 1e3 * body / double(std::max<std::size_t>(1, n_acc)),
                    r.register_seconds / double(scans), pose_limbs / double(std::max<std::size_t>(1, n_all)), pose_all / double(std::max<std::size_t>(1, n_all)));
    }
    if (posture_fitter) {
        const double n = double(std::max<std::size_t>(1, last_posture_fitted.size()));
        std::printf("the posture fits (the built-in model's) of the last round's accepted scans: pose error %.2f, %.2f deg\n", posture_limbs / n, posture_all / n);
    }

    // The learned model against a model learned directly from the true rest meshes, on held-out
    // true bodies; and the posture normalizations.
    std::vector<scan_files::RegisteredScan> true_rest;
    for (uint32_t s = 0; s < scans; ++s) true_rest.push_back({"true", rest[s], false, {}});
    learning::LearnSpec direct_spec;
    direct_spec.components = std::min<uint32_t>(50, scans - 1);
    direct_spec.posture = learning::Posture::None;
    const format::ModelData direct = learning::learn_model(default_data, true_rest, direct_spec);
    const std::vector<unsigned char> final_bytes = file_bytes(spec.out_dir + "/model.sscape");
    const std::string last_model = spec.out_dir + "/round_" + std::to_string(reports.back().round - 1) + "/model.sscape";
    const format::ModelData registered_with = format::read_model_file(last_model);
    learning::LearnSpec wide = spec.learn;
    wide.components = std::min<uint32_t>(50, uint32_t(last_accepted.size()) - 1);
    wide.posture = learning::Posture::Skeleton;
    // As the bootstrap learns (with the posture fits when it has them), and with the rounds' own fits.
    const format::ModelData own_fits = learning::learn_model(registered_with, last_accepted, wide);
    wide.posture_model = std::make_shared<const format::ModelData>(default_data);
    const format::ModelData skeleton = posture_fitter ? learning::learn_model(registered_with, last_posture_fitted, wide) : own_fits;
    wide.posture_model = nullptr;
    const format::ModelData known_pose = learning::learn_model(registered_with, last_true_pose, wide);
    wide.posture = learning::Posture::None;
    const format::ModelData none = learning::learn_model(registered_with, last_accepted, wide);
    wide.posture = learning::Posture::Laplacian;
    const format::ModelData laplacian = learning::learn_model(registered_with, last_accepted, wide);
    // The normalizations alone, without the registrations' error: learned from the true posed
    // meshes (skeleton with the true pose would give the rest meshes exactly: skinning posed them).
    std::vector<scan_files::RegisteredScan> true_posed;
    for (uint32_t s = 0; s < scans; ++s) true_posed.push_back({"true posed", truth[s], false, {}});
    learning::LearnSpec posed_spec = direct_spec;
    const format::ModelData posed_none = learning::learn_model(default_data, true_posed, posed_spec);
    posed_spec.posture = learning::Posture::Laplacian;
    const format::ModelData posed_laplacian = learning::learn_model(default_data, true_posed, posed_spec);
    std::vector<std::vector<Vector3d>> held(rest.begin() + scans, rest.begin() + scans + heldout);
    const training::SampleMatrix H = rows_of(held);
    learning::EvaluationSpec es;
    es.components = {5, 10, 20, 50};
    es.samples = 1000;
    struct Named {
        const char* name;
        const format::ModelData* m;
    };
    const format::ModelData weak_data = format::read_model(weak.data(), weak.size()), final_data = format::read_model(final_bytes.data(), final_bytes.size());
    std::printf("\nheld-out true bodies (%u), rest posture: generalization / specificity, mm\n%-38s", heldout, "model");
    for (uint32_t k : es.components) std::printf("   k=%-2u gen   spec", k);
    std::printf("\n");
    for (const Named& n : {Named{start == "template" ? "start: the template alone" : "weak start (50 true bodies, 5 comp)", &weak_data}, Named{"bootstrapped (final round)", &final_data},
                           Named{"from final registrations, skeleton", &skeleton}, Named{"  the same, unposed with the true pose", &known_pose},
                           Named{posture_fitter ? "  the same, each round's own fits" : nullptr, &own_fits}, Named{"from final registrations, none", &none}, Named{"from final registrations, laplacian", &laplacian},
                           Named{"from the true rest meshes", &direct}, Named{"from the true posed meshes, none", &posed_none},
                           Named{"from the true posed meshes, laplacian", &posed_laplacian}}) {
        if (!n.name) continue;  // a line this run has not
        std::printf("%-38s", n.name);
        if (n.m->shape.stddev.empty()) {  // the template alone has nothing to measure
            std::printf("   (no shape components)\n");
            continue;
        }
        const auto q = learning::evaluate_model(*n.m, H, es);
        for (uint32_t k : es.components) {
            const auto it = std::find_if(q.begin(), q.end(), [&](const training::QualityPoint& p) { return p.components == k; });
            if (it == q.end()) std::printf("   %14s", "-");
            else std::printf("   %6.2f %6.2f", it->generalization * 1e3, it->specificity * 1e3);
        }
        std::printf("\n");
    }
    std::printf("\nheld-out true bodies, rest posture: generalization by surface distance (slide along the surface not counted), mm\n%-38s", "model");
    for (uint32_t k : es.components) std::printf("   k=%-2u", k);
    std::printf("\n");
    ThreadPool surface_pool(threads ? threads : std::max(1u, std::thread::hardware_concurrency()));
    for (const Named& n : {Named{"bootstrapped (final round)", &final_data}, Named{"from final registrations, skeleton", &skeleton},
                           Named{"  the same, unposed with the true pose", &known_pose},
                           Named{posture_fitter ? "  the same, each round's own fits" : nullptr, &own_fits}, Named{"from final registrations, none", &none},
                           Named{"from final registrations, laplacian", &laplacian}, Named{"from the true rest meshes", &direct}}) {
        if (!n.name) continue;
        std::printf("%-38s", n.name);
        for (double g : surface_generalization(*n.m, held, es.components, surface_pool)) g < 0 ? std::printf("   %5s", "-") : std::printf("   %5.2f", 1e3 * g);
        std::printf("\n");
        std::fflush(stdout);
    }
    std::printf("\nthe mean shape's distance from the true rest meshes' model's mean (mean offset taken off)\n");
    print_mean_offset("from final registrations, skeleton", skeleton, direct);
    print_mean_offset("  the same, unposed with the true pose", known_pose, direct);
    print_mean_offset("from final registrations, none", none, direct);
    print_mean_offset("from final registrations, laplacian", laplacian, direct);
    component_picture(out + "/components_skeleton.png", skeleton, "posture skeleton");
    component_picture(out + "/components_none.png", none, "posture none");
    component_picture(out + "/components_laplacian.png", laplacian, "posture laplacian");
    std::printf("\nwrote %s/components_skeleton.png, components_none.png and components_laplacian.png; contact sheets in %s/round_N; %.0f s in all\n", out.c_str(),
                spec.out_dir.c_str(), now());
    return 0;
}
