// `sscape bootstrap`: a model from a folder of raw scans by rounds of registration, inspection and
// learning, each round's files kept under the output folder, resumable; through the offline C API
// (sscape_offline.h), as the Python pipeline runs it.
#include "cli.hpp"
#include "progress.hpp"

#include "common/files.hpp"

#include <sscape/sscape_offline.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace ssc::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
    std::string scans, init, out, posture = "skeleton", posture_model, units, up, decisions, attributes, name = "sscape-learned", license;
    uint32_t rounds = 3, components = 20, threads = 0, segment_components = 0;
    double segment_band_mm = 80;
    bool scale = false, template_only = false, fit_segments = true;  // add_bootstrap: the library's default
};

int run_bootstrap(const Options& o) {
    const auto t0 = std::chrono::steady_clock::now();
    {  // too few scans is a usage error (exit 2), found before anything is read
        ssc_scan_list* list = nullptr;
        check(ssc_scan_list_create(o.scans.c_str(), &list), o.scans);
        const uint32_t n = ssc_scan_list_count(list);
        ssc_scan_list_destroy(list);
        if (n < 3) throw UsageError(o.scans + " holds " + std::to_string(n) + " scans (.ply or .obj); bootstrapping needs at least 3");
    }
    ssc_bootstrap_def def;
    ssc_bootstrap_def_init(&def, sizeof def);
    def.scans_dir = o.scans.c_str();
    def.out_dir = o.out.c_str();
    def.init_model_path = o.init.empty() ? nullptr : o.init.c_str();
    def.template_only = o.template_only;
    def.components = o.components;
    def.posture = o.posture == "none" ? SSC_POSTURE_NONE : o.posture == "laplacian" ? SSC_POSTURE_LAPLACIAN : SSC_POSTURE_SKELETON;
    def.scale = o.scale;
    def.segment_components = o.segment_components;
    def.segment_band = float(o.segment_band_mm * 1e-3);
    def.fit_segments = o.fit_segments;
    def.units = o.units.empty() ? nullptr : o.units.c_str();
    def.up = o.up.empty() ? nullptr : o.up.c_str();
    def.decisions_path = o.decisions.empty() ? nullptr : o.decisions.c_str();
    def.attributes_path = o.attributes.empty() ? nullptr : o.attributes.c_str();
    def.name = o.name.c_str();
    def.license = o.license.empty() ? nullptr : o.license.c_str();
    def.threads = o.threads;
    def.posture_model_path = o.posture_model.empty() ? nullptr : o.posture_model == "own" ? "" : o.posture_model.c_str();
    ssc_bootstrap* b = nullptr;
    {
        std::unique_ptr<ssc_context, void (*)(ssc_context*)> context(new_context(), ssc_context_destroy);
        check(ssc_bootstrap_create(context.get(), &def, &b), "bootstrap");
    }
    std::unique_ptr<ssc_bootstrap, void (*)(ssc_bootstrap*)> owned(b, ssc_bootstrap_destroy);
    std::printf("%u scans in %s; %u rounds from %s%s; output in %s\n", ssc_bootstrap_scan_count(b), o.scans.c_str(), o.rounds,
                o.template_only ? "the template alone of " : "", o.init.empty() ? "the built-in model" : o.init.c_str(), o.out.c_str());
    struct Lines {
        Progress progress;
        std::chrono::steady_clock::time_point t0;
        explicit Lines(std::chrono::steady_clock::time_point t) : progress("bootstrap"), t0(t) {}
    } lines(t0);
    const ssc_line_fn say = [](void* user, const char* line) {
        auto* l = static_cast<Lines*>(user);
        l->progress.clear();
        std::printf("[%6.0f s] %s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - l->t0).count(), line);
        std::fflush(stdout);
        return Progress::interrupted() ? 1 : 0;
    };
    const ssc_status status = ssc_bootstrap_run(b, o.rounds, say, &lines);
    lines.progress.clear();
    if (status == SSC_ERROR_CANCELLED) {
        std::fprintf(stderr, "sscape bootstrap: cancelled (Ctrl-C); what is done stays in %s, run the same command to resume\n", o.out.c_str());
        return 130;
    }
    check(status, "bootstrap");
    std::printf("%s", read_regular_file((fs::path(o.out) / "rounds.csv").string(), 1ull << 20).c_str());
    std::printf("wrote %s/model.sscape (round %u's model), %s/rounds.csv; each round's registrations, decisions.csv and contact sheets are in "
                "%s/round_N\n",
                o.out.c_str(), o.rounds, o.out.c_str(), o.out.c_str());
    return 0;
}

}  // namespace

Run add_bootstrap(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand(
        "bootstrap", "learn a model from a folder of raw scans: register every scan, accept or reject each registration by its quality "
                     "per body region, its mesh and its joint angles, learn a model from the accepted ones, and register again with it, "
                     "for several rounds; every round's files stay on disk and a stopped run resumes");
    c->add_option("SCANS_DIR", o->scans, "the scans: every .ply and .obj in the folder (landmarks NAME.lnd beside a scan are used)")
        ->required()->check(CLI::ExistingDirectory.description(""));
    c->add_option("--init", o->init, "the starting model (default: the built-in model)")->type_name("MODEL.sscape")->check(CLI::ExistingFile.description(""));
    c->add_option("-o,--output", o->out, "the output folder: round_N/ per round, model.sscape (the last round's), rounds.csv")
        ->required()->type_name("OUT_DIR");
    c->add_option("--rounds", o->rounds, "rounds of registration and learning (default 3)")->check(CLI::Range(1u, 100u));
    c->add_option("--components", o->components, "shape components of each learned model (default 20; fewer when fewer scans are accepted)")
        ->check(CLI::Range(1u, 1000u));
    c->add_option("--posture", o->posture, "posture normalization before PCA: skeleton (default), laplacian or none")->check(CLI::IsMember(kPostureNames));
    c->add_option("--posture-model", o->posture_model,
                  "skeleton posture normalization: unpose each accepted registration with this model's fit to its scan, made once per "
                  "scan (default: the built-in model, whose shape space holds no posture, where it shares the starting model's mesh and "
                  "skeleton); own: with each round's own fit")
        ->type_name("MODEL.sscape|own");
    c->add_flag("--template-only", o->template_only, "start from the starting model's template alone (its mean body, skeleton and "
                                                     "skinning; no shape components): the weakest start");
    c->add_flag("--scale", o->scale, "learn with Procrustes alignment with scale (proportions only, no stature)");
    c->add_option("--segment-components", o->segment_components,
                  "also learn a shape space per body segment (head, arms, torso, legs) with this many components each (default 0: none)")
        ->check(CLI::Range(0u, 1000u));
    c->add_option("--segment-band", o->segment_band_mm, "millimetres on each side of a segment border over which segments blend (default 80)")
        ->check(CLI::Range(5.0, 500.0));
    ssc_bootstrap_def defaults;
    ssc_bootstrap_def_init(&defaults, sizeof defaults);
    o->fit_segments = defaults.fit_segments != 0;
    c->add_flag("--fit-segments,!--no-fit-segments", o->fit_segments,
                "register with each round's segment shape spaces in the model fit (as sscape register --segments: the default), where "
                "its model has them: a starting model that has them, or --segment-components; --no-fit-segments: the whole body's only");
    c->add_option("--units", o->units, "units of the scans and landmark files (default: metres for scans, millimetres for .lnd)")
        ->check(CLI::IsMember({"m", "cm", "mm"}).description(""))->type_name("m|cm|mm");
    c->add_option("--up", o->up, "the scans' up axis (default y)")->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z"}).description(""));
    c->add_option("--decisions", o->decisions, "a person's verdicts that override the automatic ones in every round: a round's decisions.csv "
                                               "with edited rows marked 'person' in the by column (rows marked 'auto' are ignored)")
        ->type_name("FILE.csv")->check(CLI::ExistingFile.description(""));
    c->add_option("--attributes", o->attributes, "CSV of known attributes: a header scan,NAME,..., one row per scan named by its file stem; "
                                                 "each round's model learns them from its accepted scans")
        ->type_name("FILE.csv")->check(CLI::ExistingFile.description(""));
    c->add_option("--name", o->name, "the learned models' name (default sscape-learned)");
    c->add_option("--license", o->license, "the learned models' licence, the scans' owner's to give (default: unspecified)");
    c->add_option("--threads", o->threads, "worker threads (default: all)")->check(CLI::Range(0u, 256u));
    return [o] { return run_bootstrap(*o); };
}

}  // namespace ssc::cli
