// `sscape evaluate`: compactness, generalization and specificity (learning/evaluate_learning.hpp)
// of learning from registrations, per posture normalization, or of given models (bootstrapping's
// rounds) against registrations; a CSV and three PNG plots. An offline tool: it links the C++
// learning library.
#include "cli.hpp"

#include "capi/cpp_access.hpp"
#include "common/files.hpp"
#include "common/output_paths.hpp"
#include "learning/evaluate_learning.hpp"
#include "scan_files/registration_record.hpp"
#include "render/plot.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace ssc::cli {
namespace {

struct Options {
    std::vector<std::string> registrations, postures = {"skeleton"}, models;
    std::vector<uint32_t> components;
    std::vector<std::string> sizes;
    std::string model, out;
    uint32_t folds = 0, samples = 10000, threads = 0;
    bool scale = false;
};

struct Series {
    std::string name;
    std::vector<training::QualityPoint> points;
};

// The three plots, each PREFIX_NAME.png beside PREFIX.csv.
const char* const kPlots[3] = {"compactness", "generalization", "specificity"};

void write_report(const std::string& prefix, const std::vector<Series>& series, bool given_models) {
    std::ostringstream csv;
    csv << "series,components,compactness,generalization_mm,specificity_mm\n";
    for (const auto& s : series)
        for (const auto& q : s.points)
            csv << s.name << "," << q.components << "," << q.compactness << "," << q.generalization * 1e3 << "," << q.specificity * 1e3 << "\n";
    const std::string text = csv.str();
    write_file_atomically(prefix + ".csv", text.data(), text.size());
    std::printf("wrote %s.csv\n", prefix.c_str());
    const char* const* titles = kPlots;
    const char* labels[3] = {given_models ? "share of the model's own variance (cumulative)" : "explained variance (cumulative share)",
                             given_models ? "mean vertex error reconstructing the registrations (mm)" : "mean vertex error on unseen registrations (mm)",
                             "mean vertex distance to the nearest registration (mm)"};
    for (int m = 0; m < 3; ++m) {
        render::LinePlot plot;
        plot.title = titles[m];
        plot.x_label = "number of components";
        plot.y_label = labels[m];
        for (std::size_t s = 0; s < series.size(); ++s) {
            render::LineSeries line;
            line.name = series[s].name;
            for (const auto& q : series[s].points) {
                line.x.push_back(q.components);
                line.y.push_back(m == 0 ? q.compactness : 1e3 * (m == 1 ? q.generalization : q.specificity));
            }
            if (s == 0) plot.x = line.x, plot.y = line.y, plot.name = line.name;
            else plot.more.push_back(line);
        }
        const std::string path = prefix + "_" + titles[m] + ".png";
        render::write_line_plot(path, plot);
        std::printf("wrote %s\n", path.c_str());
    }
}

int run_evaluate(const Options& o) {
    const auto t0 = std::chrono::steady_clock::now();
    auto say = [&](const std::string& stage) {
        std::printf("[%6.1f s] %s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), stage.c_str());
        std::fflush(stdout);
    };
    std::vector<std::string> written = {o.out + ".csv"};
    for (const char* t : kPlots) written.push_back(o.out + "_" + t + ".png");
    std::vector<std::string> inputs = o.registrations;
    inputs.insert(inputs.end(), o.models.begin(), o.models.end());
    inputs.push_back(o.model);
    for (const auto& w : written) refuse_output_over_input(w, inputs);
    OutputFiles outputs(written);  // the CSV and the three plots, or nothing (a failed plot once left the CSV)
    ssc_model* handle = load_model(o.model);
    Handles guard(handle);
    const Model& model = model_of(handle);
    std::vector<learning::Posture> postures;
    for (const auto& p : o.postures) postures.push_back(learning::posture_from_name(p));
    bool need_fit = false;
    for (auto p : postures) need_fit |= p == learning::Posture::Skeleton;
    std::vector<scan_files::RegisteredScan> scans;
    for (const auto& path : o.registrations) scans.push_back(scan_files::read_registration_record(path, model, need_fit).registered);
    if (scans.size() < 3) throw UsageError("evaluation needs at least 3 registrations (" + std::to_string(scans.size()) + " given)");
    learning::EvaluationSpec spec;
    spec.components = o.components;
    spec.folds = o.folds;
    spec.samples = o.samples;

    std::vector<Series> series;
    if (!o.sizes.empty()) {
        if (!o.models.empty() || postures.size() != 1) throw UsageError("--training-sizes: one --posture, no --models");
        std::vector<uint32_t> sizes;
        for (const auto& s : o.sizes) {
            if (s == "all") {
                sizes.push_back(0);
                continue;
            }
            char* end = nullptr;
            const unsigned long n = std::strtoul(s.c_str(), &end, 10);
            if (s.empty() || *end || n < 3 || n > 10000000) throw UsageError("--training-sizes: '" + s + "' is not a number of registrations (3 or more) or 'all'");
            sizes.push_back(uint32_t(n));
        }
        say("posture normalization " + o.postures[0] + ": " + std::to_string(scans.size()) + " registrations, every fifth held out");
        const training::SampleMatrix X = learning::normalized_bodies(model, scans, postures[0], o.scale, o.threads);
        for (const auto& q : learning::evaluate_training_sizes(X, sizes, spec, say)) series.push_back({std::to_string(q.size) + " scans", q.points});
        if (series.size() < sizes.size()) std::printf("(sizes beyond the %zu registrations not held out are left out)\n", scans.size() - scans.size() / 5);
    } else if (o.models.empty()) {
        for (std::size_t i = 0; i < postures.size(); ++i) {
            say("posture normalization " + o.postures[i] + ": " + std::to_string(scans.size()) + " registrations");
            const training::SampleMatrix X = learning::normalized_bodies(model, scans, postures[i], o.scale, o.threads);
            series.push_back({"posture " + o.postures[i], learning::evaluate_learning(X, spec, say)});
        }
    } else {
        if (postures.size() != 1) throw UsageError("--models: the registrations are normalized one way; give one --posture");
        const training::SampleMatrix X = learning::normalized_bodies(model, scans, postures[0], o.scale, o.threads);
        for (const auto& path : o.models) {
            say("model " + path + " against " + std::to_string(scans.size()) + " registrations");
            // Named by file stem, or folder/stem where stems repeat (bootstrapping's round_N/model).
            const std::filesystem::path p(path);
            std::size_t same = 0;
            for (const auto& other : o.models) same += std::filesystem::path(other).stem() == p.stem();
            const std::string name = same > 1 ? p.parent_path().filename().string() + "/" + p.stem().string() : p.stem().string();
            const format::ModelData other = format::read_model_file(path);
            // Registrations are in --model's mesh: a model of another mesh with as many vertices
            // once ran and reported errors of 600 mm.
            if (other.mesh.triangles != model.data().mesh.triangles)
                throw std::runtime_error(path + ": its mesh is not the one the registrations were made in (" + (o.model.empty() ? "the built-in model" : o.model) +
                                         "'s): its triangles differ; evaluate models of the registrations' template");
            series.push_back({name, learning::evaluate_model(other, X, spec)});
        }
    }
    std::printf("%-24s  %10s  %11s  %14s  %14s\n", "series", "components", "compactness", "generalization", "specificity");
    for (const auto& s : series)
        for (const auto& q : s.points)
            std::printf("%-24s  %10u  %11.4f  %11.2f mm  %11.2f mm\n", s.name.c_str(), q.components, q.compactness, q.generalization * 1e3,
                        q.specificity * 1e3);
    write_report(o.out, series, !o.models.empty());
    outputs.keep();
    return 0;
}

}  // namespace

Run add_evaluate(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand(
        "evaluate", "measure shape spaces learned from registrations (or given models) by compactness, generalization (cross-validated "
                    "reconstruction of unseen registrations) and specificity (random bodies against the nearest registration); "
                    "writes PREFIX.csv and PREFIX_compactness|generalization|specificity.png");
    c->add_option("registrations", o->registrations, "registered meshes (.ply or .obj) with their reports beside them, as sscape register "
                                                     "and sscape bootstrap write them")
        ->required()->check(CLI::ExistingFile.description(""));
    c->add_option("--model", o->model, "the model the scans were registered with (default: the built-in model)")
        ->type_name("MODEL.sscape")->check(CLI::ExistingFile.description(""));
    c->add_option("-o,--output", o->out, "the prefix of the CSV and the plots")->required()->type_name("PREFIX");
    c->add_option("--posture", o->postures, "posture normalizations to compare, each a curve (default skeleton)")
        ->delimiter(',')->check(CLI::IsMember(kPostureNames))->type_name("none,skeleton,laplacian");
    c->add_option("--models", o->models, "instead of learning, measure these models (bootstrapping's rounds, say) against the registrations")
        ->delimiter(',')->check(CLI::ExistingFile.description(""))->type_name("A.sscape,B.sscape");
    c->add_flag("--scale", o->scale, "Procrustes alignment with scale: compare shapes, sizes removed");
    c->add_option("--training-sizes", o->sizes, "instead, learn from this many of the registrations each (every fifth held out for "
                                                "generalization): a curve per size")
        ->delimiter(',')->type_name("50,100,1000,all");
    c->add_option("--components", o->components, "the numbers of components measured (default 1 to 10, then every 5th to 50, within reach)")
        ->delimiter(',')->check(CLI::Range(1u, 1000u))->type_name("K,...");
    c->add_option("--folds", o->folds, "cross-validation folds (default: leave-one-out up to 100 registrations, 10 above)")
        ->check(CLI::Range(2u, 100000u));
    c->add_option("--samples", o->samples, "random bodies per number of components for specificity (default 10000)")->check(CLI::Range(1u, 1000000u));
    c->add_option("--threads", o->threads, "worker threads of the posture normalization (default: all)")->check(CLI::Range(0u, 256u));
    return [o] { return run_evaluate(*o); };
}

}  // namespace ssc::cli
