// `sscape bootstrap`: a model from a folder of raw scans by rounds of registration, inspection and
// learning (learning/bootstrap.hpp), each round's files kept under the output folder, resumable.
// An offline tool like `sscape learn`: it links the C++ learning library.
#include "cli.hpp"
#include "progress.hpp"

#include "capi/cpp_access.hpp"
#include "common/error.hpp"
#include "common/files.hpp"
#include "learning/bootstrap.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace ssc::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
    std::string scans, init, out, posture = "skeleton", units, up, decisions, attributes, name = "sscape-learned", license;
    uint32_t rounds = 3, components = 20, threads = 0, segment_components = 0;
    double segment_band_mm = 80;
    bool scale = false, template_only = false;
};

// The scans: every .ply and .obj in the folder, by name; landmarks NAME.lnd beside a scan (or, for
// the simulator's PREFIX_scan.ply, PREFIX.lnd).
std::vector<learning::ScanInput> find_scans(const std::string& folder) {
    std::vector<learning::ScanInput> out;
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (!entry.is_regular_file()) continue;
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (ext != ".ply" && ext != ".obj") continue;
        learning::ScanInput s;
        s.name = entry.path().stem().string();
        s.path = entry.path().string();
        fs::path lnd = entry.path();
        lnd.replace_extension(".lnd");
        const std::string suffix = "_scan";
        if (!fs::exists(lnd) && s.name.size() > suffix.size() && s.name.compare(s.name.size() - suffix.size(), suffix.size(), suffix) == 0)
            lnd = entry.path().parent_path() / (s.name.substr(0, s.name.size() - suffix.size()) + ".lnd");
        if (fs::exists(lnd)) s.landmarks = lnd.string();
        out.push_back(s);
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return out;
}

int run_bootstrap(const Options& o) {
    const auto t0 = std::chrono::steady_clock::now();
    learning::BootstrapSpec spec;
    spec.scans = find_scans(o.scans);
    if (spec.scans.size() < 3)
        throw UsageError(o.scans + " holds " + std::to_string(spec.scans.size()) + " scans (.ply or .obj); bootstrapping needs at least 3");
    spec.out_dir = o.out;
    spec.rounds = o.rounds;
    spec.threads = o.threads;
    if (!o.units.empty()) spec.scan_units_to_metres = spec.lnd_units_to_metres = units_to_metres(o.units);
    if (!o.up.empty()) spec.up = o.up;
    spec.learn.components = o.components;
    spec.learn.posture = learning::posture_from_name(o.posture);
    spec.learn.segment_components = o.segment_components;
    spec.learn.scale = o.scale;
    spec.learn.segment_band = o.segment_band_mm * 1e-3;
    spec.learn.name = o.name;
    if (!o.license.empty()) spec.learn.license = o.license;
    if (!o.decisions.empty()) spec.decisions = learning::read_decisions(o.decisions);
    if (!o.attributes.empty()) spec.attributes = learning::read_attribute_table(o.attributes);

    std::vector<unsigned char> start;
    if (o.init.empty()) {
        ssc_model* handle = load_model("");
        Handles guard(handle);
        start = format::write_model(model_of(handle).data());
    } else {
        const std::string bytes = read_regular_file(o.init, 1ull << 30);
        start.assign(bytes.begin(), bytes.end());
    }
    if (o.template_only) start = format::write_model(learning::template_only(format::read_model(start.data(), start.size())));
    std::printf("%zu scans in %s; %u rounds from %s%s; output in %s\n", spec.scans.size(), o.scans.c_str(), spec.rounds,
                o.template_only ? "the template alone of " : "", o.init.empty() ? "the built-in model" : o.init.c_str(), o.out.c_str());
    Progress progress("bootstrap");
    std::vector<learning::RoundReport> rounds;
    try {
        rounds = learning::bootstrap(start, spec, [&](const std::string& line) {
            progress.clear();
            std::printf("[%6.0f s] %s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), line.c_str());
            std::fflush(stdout);
            return !Progress::interrupted();
        });
    } catch (const Error& e) {
        if (e.status() != SSC_ERROR_CANCELLED) throw;
        progress.clear();
        std::fprintf(stderr, "sscape bootstrap: cancelled (Ctrl-C); what is done stays in %s, run the same command to resume\n", o.out.c_str());
        return 130;
    }
    progress.clear();
    std::printf("round  accepted  rejected  failed  register s  learn s  components\n");
    for (const auto& r : rounds)
        std::printf("%5u  %8zu  %8zu  %6zu  %10.1f  %7.1f  %10u\n", r.round, r.accepted, r.rejected, r.failed, r.register_seconds, r.learn_seconds,
                    r.components);
    std::printf("wrote %s/model.sscape (round %u's model), %s/rounds.csv; each round's registrations, decisions.csv and contact sheets are in "
                "%s/round_N\n",
                o.out.c_str(), rounds.back().round, o.out.c_str(), o.out.c_str());
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
    c->add_option("--posture", o->posture, "posture normalization before PCA: skeleton (default) or none")->check(CLI::IsMember({"none", "skeleton"}));
    c->add_flag("--template-only", o->template_only, "start from the starting model's template alone (its mean body, skeleton and "
                                                     "skinning; no shape components): the weakest start");
    c->add_flag("--scale", o->scale, "learn with Procrustes alignment with scale (proportions only, no stature)");
    c->add_option("--segment-components", o->segment_components,
                  "also learn a shape space per body segment (head, arms, torso, legs) with this many components each (default 0: none)")
        ->check(CLI::Range(0u, 1000u));
    c->add_option("--segment-band", o->segment_band_mm, "millimetres on each side of a segment border over which segments blend (default 80)")
        ->check(CLI::Range(5.0, 500.0));
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
