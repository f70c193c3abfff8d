// Scan registration accuracy and speed on simulated scans with known correspondence.
//
//   sscape_register_bench [--trials N] [--init model|rigid|rbf] [--constant] [--no-segments|--all-segments] [--segment-prior W] [--stiffness B] [--threads N]
//                         [--makehuman DIR] [--landmarks [--landmark-noise SD] [--landmark-sigma S] [--landmark-weight C]]
//                         [--png PREFIX] [--compare OUT.png]
// --compare: the papers' comparison on the same scans: the model fit alone, rigid + deformation,
// rbf + deformation (both from the landmarks), model fit + deformation with relaxed and with
// constant weights, and relaxed with the landmarks too; a table and the share of vertices within
// each correspondence error as a plot.
// --landmarks: the CAESAR landmarks (but the hands'), exact, join the scan (always with --init rigid or rbf);
// --landmark-noise SD: placed with Gaussian error (metres per axis); --landmark-sigma S: the model
// fit's FitOptions::landmark_sigma; --landmark-weight C: the deformation's first landmark weight.
// --fit-points N, --fit-iterations N: the model fit's FitOptions::max_points and max_iterations.
//
// Each trial, by default: a random body and pose of the default model, with smooth bumps and dents
// of up to 2 cm that the model cannot represent, scanned (50,000 points, 1 mm noise, 10 % of the
// surface in holes) and registered. With --makehuman (the shared/makehuman assets): a body of the
// MakeHuman population with the neck, head and arm/leg modifiers that training leaves out set at
// random (half their range; not those that move a part bodily), in the scanning pose with small random changes, scanned by a
// booth of 8 depth cameras (4 columns, 2 heights; 1 mm noise; 60,000 points kept). Vertex i of the true body is vertex i of the template, so the
// correspondence error (registered vertex to true vertex) catches sliding along the surface that
// surface distances hide.
#include "paths.hpp"

#include "registration/register_scan.hpp"
#include "render/plot.hpp"
#include "render/registration_picture.hpp"
#include "registration/registration_quality.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/simulate.hpp"
#ifdef SSCAPE_WITH_TRAINING
#include "training/makehuman/assets.hpp"
#include "training/population.hpp"
#endif
#include "sscape_format/model_io.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <thread>


using namespace ssc;
using Eigen::Vector3d;

namespace {

double mean_distance(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, const std::vector<uint8_t>* only = nullptr,
                     bool inside = true) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t v = 0; v < a.size(); ++v)
        if (!only || bool((*only)[v]) == inside) sum += (a[v] - b[v]).norm(), ++n;
    return n ? sum / double(n) : 0;
}

// The legs' vertices' vertical error (x - truth, metres, + up), mean per sixth of the legs' height
// in `heights` (ankle to crotch); with centre, less the legs' mean (for shapes in another frame).
std::array<double, 6> legs_by_height(const std::vector<Vector3d>& x, const std::vector<Vector3d>& truth, const std::vector<Vector3d>& heights,
                                     const registration::BodyRegions& regions, bool centre) {
    auto is_leg = [&](std::size_t v) { return regions.of_vertex[v] >= 0 && regions.names[std::size_t(regions.of_vertex[v])] == "legs"; };
    double lo = 1e9, hi = -1e9, all = 0, n = 0;
    for (std::size_t v = 0; v < x.size(); ++v)
        if (is_leg(v)) lo = std::min(lo, heights[v].y()), hi = std::max(hi, heights[v].y()), all += (x[v] - truth[v]).y(), n += 1;
    std::array<double, 6> sum{}, count{};
    for (std::size_t v = 0; v < x.size(); ++v) {
        if (!is_leg(v)) continue;
        const std::size_t b = std::min<std::size_t>(5, std::size_t(6 * (heights[v].y() - lo) / std::max(hi - lo, 1e-9)));
        sum[b] += (x[v] - truth[v]).y() - (centre ? all / std::max(n, 1.0) : 0.0), count[b] += 1;
    }
    for (std::size_t b = 0; b < 6; ++b) sum[b] = count[b] > 0 ? sum[b] / count[b] : 0;
    return sum;
}

void print_sixths(const char* what, const std::array<double, 6>& a) {
    std::printf(" %s", what);
    for (double x : a) std::printf(" %.1f", x * 1e3);
}

}  // namespace

int main(int argc, char** argv) {
    int trials = 5;
    std::string png, makehuman, compare;
    bool with_landmarks = false;
    double landmark_noise = 0;  // metres, per axis
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    registration::RegistrationOptions options;
    double segment_prior = options.fit.segment_prior;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--trials" && i + 1 < argc) trials = std::atoi(argv[++i]);
        else if (a == "--threads" && i + 1 < argc) threads = unsigned(std::max(1, std::atoi(argv[++i])));
        else if (a == "--stiffness" && i + 1 < argc) options.stiffness = std::atof(argv[++i]);
        else if (a == "--gamma" && i + 1 < argc) options.gamma = std::atof(argv[++i]);
        else if (a == "--iterations" && i + 1 < argc) options.max_iterations = uint32_t(std::atoi(argv[++i]));
        else if (a == "--png" && i + 1 < argc) png = argv[++i];
        else if (a == "--makehuman" && i + 1 < argc) makehuman = argv[++i];
        else if (a == "--compare" && i + 1 < argc) compare = argv[++i];
        else if (a == "--landmarks") with_landmarks = true;
        else if (a == "--segments") options.segments = true;  // the default
        else if (a == "--no-segments") options.segments = false;
        else if (a == "--all-segments") options.segments = true, options.segments_left_out.clear();
        else if (a == "--segment-prior" && i + 1 < argc) segment_prior = std::atof(argv[++i]);
        else if (a == "--landmark-noise" && i + 1 < argc) landmark_noise = std::atof(argv[++i]);
        else if (a == "--landmark-weight" && i + 1 < argc) options.landmarks = std::atof(argv[++i]);
        else if (a == "--landmark-sigma" && i + 1 < argc) options.fit.landmark_sigma = std::atof(argv[++i]);
        else if (a == "--fit-points" && i + 1 < argc) options.fit.max_points = uint32_t(std::atoi(argv[++i]));
        else if (a == "--fit-iterations" && i + 1 < argc) options.fit.max_iterations = uint32_t(std::atoi(argv[++i]));
        else if (a == "--constant") options.schedule = registration::Schedule::Constant;
        else if (a == "--init" && i + 1 < argc) {
            const std::string v = argv[++i];
            options.initialisation = v == "rigid" ? registration::Initialisation::Rigid
                                     : v == "rbf" ? registration::Initialisation::Rbf
                                                  : registration::Initialisation::Model;
        } else {
            std::fprintf(stderr, "usage: sscape_register_bench [--trials N] [--init model|rigid|rbf] [--constant] [--no-segments|--all-segments] [--segment-prior W] [--stiffness B] [--threads N] [--makehuman DIR] [--landmarks [--landmark-noise SD] [--landmark-sigma S] [--landmark-weight C]] [--png PREFIX]\n");
            return 2;
        }
    }
    const Model model(format::read_model_file(sscape_paths::default_model_file()), nullptr);
    const fitting::LinearModel lin(model, model.component_count(), nullptr, options.segments, options.segments_left_out);
    options.fit.segment_prior = segment_prior;
    const std::vector<uint32_t> triangles(model.data().mesh.triangles.begin(), model.data().mesh.triangles.end());
    std::vector<uint8_t> hand(model.vertex_count(), 0);
    for (const auto& set : model.data().vertex_sets)
        if (set.name == "hands")
            for (uint32_t v : set.vertices) hand[v] = 1;
    ThreadPool pool(threads);
    std::mt19937 rng(2026);
#ifdef SSCAPE_WITH_TRAINING
    // The MakeHuman population, then the modifiers training leaves out, drawn per body.
    training::mh::Assets assets;
    std::vector<training::BodyParams> people;
    std::size_t trained_modifiers = 0;
    if (!makehuman.empty()) {
        assets = training::mh::load_assets(makehuman);
        training::PopulationSpec ps;
        ps.count = uint32_t(trials);
        ps.seed = 77;
        people = training::sample_population(assets, ps);
        trained_modifiers = assets.modifiers.size();
        training::mh::add_modifier_groups(assets, "modeling_modifiers.json", {"neck", "head", "armslegs"});
        std::printf("MakeHuman bodies: %zu modifiers the model was trained with, %zu more it was not\n", trained_modifiers,
                    assets.modifiers.size() - trained_modifiers);
    }
#else
    if (!makehuman.empty()) {
        std::fprintf(stderr, "--makehuman needs a build with training (SSCAPE_BUILD_TRAINING)\n");
        return 2;
    }
#endif
    std::printf("trial  fit corr  nrd corr  nrd corr (no hands)  hands  scan->reg mean  median  p95   <2mm  <5mm  worst region  time (fit)\n");
    std::vector<Vector3d> true_rest, best_segments_rest;  // a MakeHuman trial's true body at rest, its best approximation
    std::vector<double> fit_errors, errors, body_errors, scan_means, times, best_errors, best_tangential, best_with_segments;
    // --compare: per method, every vertex's correspondence error over the trials, and its scan
    // distances and times.
    const char* methods[] = {"model fit alone", "rigid + deformation", "rbf + deformation", "model + deformation",
                             "model + deformation, constant", "model + deformation, landmarks"};
    constexpr int kMethods = 6;
    std::vector<double> method_errors[kMethods], method_body[kMethods], method_scan[kMethods], method_time[kMethods];
    for (int t = 0; t < trials; ++t) {
        simulation::TrueBody truth;
        registration::Scan scan;
        if (makehuman.empty()) {
            truth = simulation::make_body(model, simulation::random_shape(model, rng), simulation::random_pose(model, rng, 0.3), Vector3d::Zero());
            simulation::add_bumps(truth, model, 8, rng);
            simulation::CloudSpec spec;
            spec.points = 50000;
            spec.noise = 0.001;
            spec.missing = 0.1;
            spec.outliers = 0;
            scan.cloud = simulation::simulate_cloud(model, truth, spec, rng);
        } else {
#ifdef SSCAPE_WITH_TRAINING
            const std::vector<float> xyz = training::beyond_model_body(assets, people[std::size_t(t)], trained_modifiers, rng);
            std::vector<Vector3d> rest(model.vertex_count());
            for (uint32_t v = 0; v < model.vertex_count(); ++v) rest[v] = Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
            std::vector<Vector3d> approximation;
            true_rest = rest;
            best_errors.push_back(simulation::best_approximation_error(model, rest, false, &approximation));
            if (std::getenv("SSCAPE_BENCH_VERBOSE")) {  // how much of the model's own limit lies along the surface
                const std::vector<Vector3d> normals = registration::vertex_normals(rest, triangles);
                double along = 0, across = 0;
                for (uint32_t v = 0; v < model.vertex_count(); ++v) {
                    const Vector3d e = approximation[v] - rest[v];
                    const double n = e.dot(normals[v]);
                    across += std::abs(n), along += (e - n * normals[v]).norm();
                }
                std::printf("  the model's best approximation: %.2f mm along the normal, %.2f mm along the surface\n", across / model.vertex_count() * 1e3,
                            along / model.vertex_count() * 1e3);
                best_tangential.push_back(along / model.vertex_count());
                if (!model.segments().empty()) {  // the same with the segment shape spaces added
                    best_with_segments.push_back(simulation::best_approximation_error(model, rest, false, &best_segments_rest, true));
                    std::printf("  with the segment shape spaces: %.2f mm\n", best_with_segments.back() * 1e3);
                }
            }
            truth = simulation::pose_rest_vertices(model, rest, simulation::random_pose(model, rng, 0.15), Vector3d(0, 0, 0));
            simulation::BoothSpec booth;
            scan.cloud = simulation::booth_scan(model, truth, booth, rng);
#endif
        }
        if (!compare.empty()) {
            registration::Scan with_marks = scan;
            with_marks.landmarks = simulation::simulate_landmarks(model, truth, 0.0, true, rng);
            for (int m = 1; m < kMethods; ++m) {
                registration::RegistrationOptions o = options;
                o.initialisation = m == 1 ? registration::Initialisation::Rigid : m == 2 ? registration::Initialisation::Rbf
                                                                                          : registration::Initialisation::Model;
                o.schedule = m == 4 ? registration::Schedule::Constant : registration::Schedule::Relaxed;
                const registration::Registration r = registration::register_scan(lin, m <= 2 || m == 5 ? with_marks : scan, o, {}, &pool);
                auto collect = [&](int k, const std::vector<Vector3d>& x, double scan_mean, double seconds) {
                    double sum = 0, body = 0;
                    std::size_t nb = 0;
                    for (std::size_t v = 0; v < x.size(); ++v) {
                        const double e = (x[v] - truth.vertices[v]).norm();
                        method_errors[k].push_back(e);
                        sum += e;
                        if (!hand[v]) body += e, ++nb;
                    }
                    method_body[k].push_back(body / double(nb));
                    method_scan[k].push_back(scan_mean);
                    method_time[k].push_back(seconds);
                };
                collect(m, r.vertices, r.report.quality.scan_to_registration.mean, r.report.seconds);
                if (m == 3) collect(0, simulation::fitted_vertices(model, r.fit.frames[0]), -1, r.report.fit_seconds);
            }
            std::printf("trial %d done\n", t);
            continue;
        }
        if (options.initialisation != registration::Initialisation::Model || with_landmarks)
            scan.landmarks = simulation::simulate_landmarks(model, truth, landmark_noise, true, rng);
        const registration::Registration r = registration::register_scan(lin, scan, options, {}, &pool);
        const double fit_err = r.fit.frames.empty() ? 0 : simulation::mean_vertex_error(simulation::fitted_vertices(model, r.fit.frames[0]), truth.vertices);
        const double err = mean_distance(r.vertices, truth.vertices), body = mean_distance(r.vertices, truth.vertices, &hand, false),
                     hands = mean_distance(r.vertices, truth.vertices, &hand, true);
        const auto& q = r.report.quality;
        if (std::getenv("SSCAPE_BENCH_VERBOSE")) {
            double normal = 0, tangent = 0, fnormal = 0, ftangent = 0;
            const auto fitted = simulation::fitted_vertices(model, r.fit.frames[0]);
            for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
                const Vector3d e = r.vertices[v] - truth.vertices[v], f = fitted[v] - truth.vertices[v];
                const double en = e.dot(truth.normals[v]), fn = f.dot(truth.normals[v]);
                normal += std::abs(en), tangent += (e - en * truth.normals[v]).norm();
                fnormal += std::abs(fn), ftangent += (f - fn * truth.normals[v]).norm();
            }
            const double n = double(truth.vertices.size());
            {   // correspondence error by region: normal / tangential, fit then registration
                const registration::BodyRegions regions = registration::body_regions(model.data());
                std::vector<double> sums(regions.names.size() * 4, 0.0), counts(regions.names.size(), 0.0);
                for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
                    const int g = regions.of_vertex[v];
                    if (g < 0) continue;
                    const Vector3d e = r.vertices[v] - truth.vertices[v], f = fitted[v] - truth.vertices[v];
                    const double en = e.dot(truth.normals[v]), fn = f.dot(truth.normals[v]);
                    sums[4 * g] += std::abs(fn), sums[4 * g + 1] += (f - fn * truth.normals[v]).norm();
                    sums[4 * g + 2] += std::abs(en), sums[4 * g + 3] += (e - en * truth.normals[v]).norm();
                    counts[g] += 1;
                }
                {   // the legs' error along the surface split along the leg (the surface's up) and around it
                    double along = 0, around = 0, count = 0;
                    for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
                        const int g = regions.of_vertex[v];
                        if (g < 0 || regions.names[std::size_t(g)] != "legs") continue;
                        const Vector3d& nv = truth.normals[v];
                        const Vector3d e = r.vertices[v] - truth.vertices[v], t = e - e.dot(nv) * nv;
                        const Vector3d up = Vector3d::UnitY() - nv.y() * nv;
                        if (up.norm() < 1e-6) continue;
                        const double a = t.dot(up.normalized());
                        along += std::abs(a), around += (t - a * up.normalized()).norm(), count += 1;
                    }
                    std::printf("  legs along the surface: along the leg %.1f mm, around it %.1f mm; vertical error by sixths of height, ankle to crotch (mm):",
                                along / std::max(count, 1.0) * 1e3, around / std::max(count, 1.0) * 1e3);
                    print_sixths("registration", legs_by_height(r.vertices, truth.vertices, truth.vertices, regions, false));
                    print_sixths("; fit", legs_by_height(fitted, truth.vertices, truth.vertices, regions, false));
                    if (!true_rest.empty()) {  // the fitted shape alone, at rest, against the true rest body
                        fitting::FitState at_rest = r.fit.frames[0];
                        for (auto& q : at_rest.pose) q = Eigen::Quaterniond::Identity();
                        at_rest.translation.setZero();
                        print_sixths("; fitted shape at rest (legs' mean off)",
                                     legs_by_height(simulation::fitted_vertices(model, at_rest), true_rest, true_rest, regions, true));
                        if (!best_segments_rest.empty())
                            print_sixths("; best approximation with segments", legs_by_height(best_segments_rest, true_rest, true_rest, regions, false));
                    }
                    std::printf("\n");
                }
                std::printf("  correspondence by region, normal/tangential, fit -> registration:");
                for (std::size_t g = 0; g < regions.names.size(); ++g)
                    std::printf(" %s %.1f/%.1f -> %.1f/%.1f", regions.names[g].c_str(), sums[4 * g] / counts[g] * 1e3, sums[4 * g + 1] / counts[g] * 1e3,
                                sums[4 * g + 2] / counts[g] * 1e3, sums[4 * g + 3] / counts[g] * 1e3);
                std::printf("\n");
            }
            {   // the true surface's distance to the registration and the fit, by region
                const fitting::PointIndex tindex(truth.vertices);
                const registration::BodyRegions regions = registration::body_regions(model.data());
                for (int which = 0; which < 2; ++which) {
                    const auto& x = which ? fitted : r.vertices;
                    const auto tq = registration::registration_quality(x, triangles, registration::vertex_normals(x, triangles), regions.of_vertex, regions.names,
                                                                       truth.vertices, truth.normals, true, tindex, pool);
                    std::printf("  true surface to %s: %.2f mm;", which ? "fit" : "registration", tq.scan_to_registration.mean * 1e3);
                    for (const auto& rq : tq.regions) std::printf(" %s %.2f", rq.region.c_str(), rq.scan_to_registration.mean * 1e3);
                    std::printf("\n");
                }
            }
            std::printf("  error along the normal / tangential: fit %.2f / %.2f mm, registration %.2f / %.2f mm; valid %zu of %zu; rounds %u, solves %u\n",
                        fnormal / n * 1e3, ftangent / n * 1e3, normal / n * 1e3, tangent / n * 1e3, r.report.valid, truth.vertices.size(),
                        r.report.rounds, r.report.solves);
        }
        std::string worst;
        double worst_mean = 0;
        for (const auto& region : q.regions)
            if (region.scan_to_registration.mean > worst_mean) worst_mean = region.scan_to_registration.mean, worst = region.region;
        std::printf("%5d  %5.2f mm  %5.2f mm  %8.2f mm         %5.2f  %8.2f mm    %5.2f  %5.2f  %4.0f%%  %4.0f%%  %s %.2f mm  %.2f s (%.2f)\n", t,
                    fit_err * 1e3, err * 1e3, body * 1e3, hands * 1e3, q.scan_to_registration.mean * 1e3, q.scan_to_registration.median * 1e3,
                    q.scan_to_registration.p95 * 1e3, 100 * q.below[0], 100 * q.below[1], worst.c_str(), worst_mean * 1e3, r.report.seconds,
                    r.report.fit_seconds);
        if (!png.empty()) {
            std::vector<double> e(truth.vertices.size());
            for (std::size_t v = 0; v < e.size(); ++v) e[v] = (r.vertices[v] - truth.vertices[v]).norm();
            if (std::FILE* f = std::fopen((png + std::to_string(t) + ".obj").c_str(), "w")) {  // for close-ups elsewhere
                for (const Vector3d& v : r.vertices) std::fprintf(f, "v %.6f %.6f %.6f\n", v.x(), v.y(), v.z());
                for (std::size_t i = 0; i < triangles.size(); i += 3)
                    std::fprintf(f, "f %u %u %u\n", triangles[i] + 1, triangles[i + 1] + 1, triangles[i + 2] + 1);
                std::fclose(f);
            }
            render::write_registration_picture(png + std::to_string(t) + ".png", model, render::PictureFrame{},
                                               scan.cloud.points, r.vertices, e);
            std::vector<double> ef(truth.vertices.size());
            const auto fitted = simulation::fitted_vertices(model, r.fit.frames[0]);
            for (std::size_t v = 0; v < e.size(); ++v) ef[v] = (fitted[v] - truth.vertices[v]).norm();
            render::write_registration_picture(png + std::to_string(t) + "_fit.png", model, render::PictureFrame{},
                                               scan.cloud.points, fitted, ef);
        }
        fit_errors.push_back(fit_err), errors.push_back(err), body_errors.push_back(body), scan_means.push_back(q.scan_to_registration.mean);
        times.push_back(r.report.seconds);
    }
    auto mean = [](const std::vector<double>& v) {
        double s = 0;
        for (double x : v) s += x;
        return v.empty() ? 0 : s / double(v.size());
    };
    if (!compare.empty()) {
        std::printf("%-32s %14s %14s %14s %8s\n", "method", "corr. error", "without hands", "scan to reg.", "time");
        render::LinePlot plot;
        plot.title = "registration: correspondence error";
        plot.x_label = "correspondence error (mm)";
        plot.y_label = "share of vertices within it";
        for (int k = 0; k < kMethods; ++k) {
            std::vector<double> sorted = method_errors[k], times_k = method_time[k];
            std::sort(sorted.begin(), sorted.end());
            std::sort(times_k.begin(), times_k.end());
            std::printf("%-32s %11.2f mm %11.2f mm ", methods[k], mean(method_errors[k]) * 1e3, mean(method_body[k]) * 1e3);
            if (k == 0) std::printf("%14s", "-");
            else std::printf("%11.2f mm", mean(method_scan[k]) * 1e3);
            std::printf(" %6.2f s\n", times_k[times_k.size() / 2]);
            render::LineSeries curve{methods[k], {}, {}};
            for (int mm = 0; mm <= 20; ++mm) {
                curve.x.push_back(mm);
                curve.y.push_back(double(std::upper_bound(sorted.begin(), sorted.end(), mm * 1e-3) - sorted.begin()) / double(sorted.size()));
            }
            if (k == 0) plot.name = curve.name, plot.x = curve.x, plot.y = curve.y;
            else plot.more.push_back(curve);
        }
        render::write_line_plot(compare, plot);
        if (!best_errors.empty())
            std::printf("the model's best approximation of the true bodies (rest pose, correspondence known): %.2f mm mean vertex error\n", mean(best_errors) * 1e3);
        std::printf("wrote %s (%d trials)\n", compare.c_str(), trials);
        return 0;
    }
    std::sort(times.begin(), times.end());
    std::printf("mean over %d trials: fit alone %.2f mm, registration %.2f mm (%.2f without hands), scan to registration %.2f mm, time median %.2f s\n",
                trials, mean(fit_errors) * 1e3, mean(errors) * 1e3, mean(body_errors) * 1e3, mean(scan_means) * 1e3, times[times.size() / 2]);
    if (!best_errors.empty())
        std::printf("the model's best approximation of the true bodies (rest pose, correspondence known): %.2f mm mean vertex error\n", mean(best_errors) * 1e3);
    if (!best_tangential.empty()) std::printf("  of which along the surface: %.2f mm\n", mean(best_tangential) * 1e3);
    if (!best_with_segments.empty()) std::printf("  with the model's segment shape spaces too: %.2f mm\n", mean(best_with_segments) * 1e3);
    return 0;
}
