#include "cli.hpp"
#include "progress.hpp"

#include "common/error.hpp"
#include "sscape_format/model_io.hpp"
#include "training/train.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace ssc::cli {

namespace {

int run_train(const training::TrainSpec& spec, const std::string& out) {
    if (spec.population.count <= spec.heldout + spec.components)
        throw UsageError("--bodies must exceed --heldout plus --components");
    if (spec.population.count <= spec.heldout + spec.segment_components)
        throw UsageError("--bodies must exceed --heldout plus --segment-components");
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    training::TrainReport report;
    Progress progress("train");  // on a terminal: how far the long stages are; Ctrl-C cancels
    std::string stage;
    const training::Progress log = [&](const std::string& now, uint32_t done, uint32_t total) {
        if (now != stage) {
            stage = now;
            progress.clear();
            std::printf("[%7.1f s] %s\n", elapsed(), now.c_str());
            std::fflush(stdout);
        }
        return progress.update(total ? now + ": " + std::to_string(done) + " of " + std::to_string(total) : now);
    };
    format::ModelData model;
    try {
        model = training::train_model(spec, report, log);
    } catch (const Error& e) {
        if (e.status() != SSC_ERROR_CANCELLED) throw;
        std::fprintf(stderr, "sscape train: cancelled (Ctrl-C); nothing written\n");
        return 130;
    }
    const std::vector<unsigned char> bytes = format::write_model(model);
    format::write_file(out, bytes);

    std::printf("wrote %s: %zu bytes (%.3f MB), %u vertices, %u joints, %u components, in %.1f s\n", out.c_str(), bytes.size(),
                bytes.size() / 1e6, model.vertex_count(), model.joint_count(), model.component_count(), elapsed());
    std::printf("basis quantization: worst vertex error %.4f mm with every component at +-3 SD\n", report.quantization.max_error * 1e3);
    std::printf("joint regressor, %u held-out bodies: mean error %.2f mm, max %.2f mm\n", spec.heldout,
                report.regressor_mean_error * 1e3, report.regressor_max_error * 1e3);
    auto worst = report.joint_errors;
    std::sort(worst.begin(), worst.end(), [](const auto& x, const auto& y) { return x.second > y.second; });
    std::printf("worst joints (held-out mean):");
    for (std::size_t i = 0; i < std::min<std::size_t>(5, worst.size()); ++i) std::printf(" %s %.2f mm", worst[i].first.c_str(), worst[i].second * 1e3);
    std::printf("\n");
    std::printf("%10s %12s %18s %16s\n", "components", "compactness", "generalization_mm", "specificity_mm");
    for (const auto& q : report.quality)
        std::printf("%10u %11.3f%% %18.2f %16.2f\n", q.components, 100 * q.compactness, q.generalization * 1e3, q.specificity * 1e3);
    for (const auto& png : report.plots) std::printf("plot: %s\n", png.c_str());
    print_segment_compactness(report.segments);
    for (const auto& l : report.levels)
        std::printf("level of detail %s: %u vertices, %u triangles; its vertices lie %.2f mm (mean) and %.2f mm (max) off the template's surface\n",
                    l.name.c_str(), l.vertices, l.triangles, l.offset_mean * 1e3, l.offset_max * 1e3);
    if (const auto& mtm = report.made_to_measure; mtm.bodies > 0) {
        std::printf("made to measure, %u held-out bodies (stature, chest, waist, hip requested with sex and age): "
                    "%u converged, %.2f s per body\n", mtm.bodies, mtm.converged, mtm.mean_seconds);
        std::printf("%-16s %14s %14s %22s\n", "measurement", "mean_error_mm", "worst_error_mm", "regression_start_mm");
        for (std::size_t k = 0; k < mtm.measurements.size(); ++k)
            std::printf("%-16s %14.2f %14.2f %22.2f\n", mtm.measurements[k].c_str(), mtm.mean_error[k] * 1e3, mtm.worst_error[k] * 1e3,
                        mtm.start_mean_error[k] * 1e3);
    }
    // Population measurements by sex, in centimetres.
    auto stats = [&](const std::vector<double>& v, int sex, double& mean, double& sd) {
        double s = 0, s2 = 0;
        int n = 0;
        for (std::size_t i = 0; i < v.size() && i < report.male.size(); ++i)
            if (report.male[i] == sex) s += v[i], s2 += v[i] * v[i], ++n;
        mean = n ? 100 * s / n : 0;
        sd = n > 1 ? 100 * std::sqrt(std::max(0.0, (s2 - s * s / n) / (n - 1))) : 0;
        return n;
    };
    // Published survey figures beside each row (men | women), sources printed below the table.
    struct Row {
        const char* name;
        const std::vector<double>* values;
        const char* survey;
    };
    const Row rows[] = {
        {"stature", &report.statures, "175.4 | 161.7 [1]"},
        {"chest girth (bust points)", &report.chest, "101.0 | 86.1 [3]"},
        {"waist girth (iliac crest, NHANES)", &report.waist_iliac, "102.1 | 98.0 [1]"},
        {"waist girth (natural)", &report.waist_natural, "83-98 | 78-91 [2]"},
        {"hip girth (max near trochanters)", &report.hip, "94-105 | 97-108 [2]"}};
    std::printf("%-36s %22s %22s   %s\n", "population (cm)", "men mean (sd)", "women mean (sd)", "survey men | women");
    for (const auto& row : rows) {
        double mm, ms, wm, ws;
        const int nm = stats(*row.values, 1, mm, ms), nw = stats(*row.values, 0, wm, ws);
        std::printf("%-36s %10.1f (%4.1f) n=%-4d %10.1f (%4.1f) n=%-4d   %s\n", row.name, mm, ms, nm, wm, ws, nw, row.survey);
    }
    {
        double mm, ms, wm, ws;  // stats() reports x100 (centimetres); BMI is kg/m^2
        stats(report.bmi, 1, mm, ms);
        stats(report.bmi, 0, wm, ws);
        std::printf("%-36s %10.1f (%4.1f)        %10.1f (%4.1f)          %s\n", "BMI (kg/m2, density 1010 kg/m3)", mm / 100, ms / 100, wm / 100,
                    ws / 100, "29.1 | 29.6 [1]");
    }
    std::printf("[1] US adults 20+, NHANES 2015-2016 means: Fryar et al., Mean body weight, height, waist circumference and BMI\n"
                "    among adults: United States, 1999-2000 through 2015-2016, National Health Statistics Reports 122 (2018).\n"
                "[2] Range of the age-standardised means of 19 populations aged 25-64 (waist midway between lowest rib and iliac\n"
                "    crest; hip at the widest point over the buttocks): Molarius et al., Waist and hip circumferences, and\n"
                "    waist-hip ratio in 19 populations of the WHO MONICA Project, Int J Obes 23:116-125 (1999).\n"
                "[3] Means of a published data set, recomputed from its 247 men and 260 women (sd 7.2 | 6.2): Heinz et al.,\n"
                "    Exploring relationships in body dimensions, Journal of Statistics Education 11(2) (2003). A young,\n"
                "    physically active sample, so leaner than [1]; chest taped at the nipples for men but above the breast\n"
                "    tissue for women, so the women's figure is below a bust-point girth. No national survey table of chest\n"
                "    girth was reachable when this report was written.\n");
    return 0;
}

}  // namespace

Run add_train(CLI::App& app) {
    struct Options {
        training::TrainSpec spec;
        std::string out;
        double segment_band_mm = 80;
    };
    auto o = std::make_shared<Options>();
    training::TrainSpec& s = o->spec;
    CLI::App* c = app.add_subcommand("train", "train a model from the CC0 MakeHuman assets: a sampled population of bodies, their PCA "
                                              "shape space, skeleton regressor, landmarks, sliders and a quality report");
    c->add_option("--assets", s.assets_root, "the MakeHuman asset folder (shared/makehuman)")->required()->type_name("DIR")
        ->check(CLI::ExistingDirectory.description(""));
    c->add_option("-o,--output", o->out, "the model file to write")->required()->type_name("OUT.sscape");
    c->add_option("--bodies", s.population.count, "bodies sampled from the MakeHuman modifiers")
        ->check(CLI::Range(2u, 20000u))->capture_default_str();
    c->add_option("--components", s.components, "shape components kept")->check(CLI::Range(1u, 500u))->capture_default_str();
    c->add_option("--seed", s.population.seed, "random seed of the population")->capture_default_str();
    c->add_option("--heldout", s.heldout, "bodies kept out of the joint regressor, to measure its error")->capture_default_str();
    c->add_option("--regressor-support", s.regressor_support, "body vertices per joint in the joint regressor (about)")
        ->check(CLI::Range(4u, 100000u))->capture_default_str();
    c->add_option("--made-to-measure", s.made_to_measure_bodies, "held-out bodies the made-to-measure accuracy is measured on")
        ->capture_default_str();
    c->add_option("--population-csv", s.population_csv, "write the sampled modifier values here")->type_name("FILE.csv");
    c->add_option("--report", s.report_prefix,
                  "write the quality report (compactness, generalization, specificity: CSV and plots; landmark pictures) to "
                  "files starting with PREFIX (an existing folder ending in / or a name prefix)")
        ->type_name("PREFIX");
    c->add_option("--segment-components", s.segment_components,
                  "also learn a shape space per body segment (head, arms, torso, legs) with this many components each (default 0: none)")
        ->check(CLI::Range(0u, 500u));
    c->add_option("--segment-band", o->segment_band_mm, "millimetres on each side of a segment border over which segments blend (default 80)")
        ->check(CLI::Range(5.0, 500.0));
    c->add_flag("--procrustes", s.procrustes, "rigidly align the bodies (generalized Procrustes) before PCA; MakeHuman's share one frame");
    return [o] {
        o->spec.segment_band = o->segment_band_mm * 1e-3;
        return run_train(o->spec, o->out);
    };
}

}  // namespace ssc::cli
