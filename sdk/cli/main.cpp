// `sscape`: the command line. Assembles the commands (one file each) into one CLI11 app, runs the
// one named and maps failures to exit codes: 0 done, 1 failed (a file, the library, a fit that did
// not explain its scan), 2 a usage error, 130 cancelled with Ctrl-C.
#include "cli.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

std::string version_text() {
    const uint32_t v = ssc_version();
    std::string text = "sscape " + std::to_string(SSC_VERSION_MAJOR) + "." + std::to_string(SSC_VERSION_MINOR) + "." +
                       std::to_string(SSC_VERSION_PATCH) + " (library " + std::to_string(v / 10000) + "." +
                       std::to_string(v / 100 % 100) + "." + std::to_string(v % 100);
    ssc_model* model = nullptr;
    if (ssc_model_load_default(nullptr, &model) == SSC_OK) {
        const char *name = "", *version = "";
        ssc_model_get_metadata(model, SSC_METADATA_NAME, &name);
        ssc_model_get_metadata(model, SSC_METADATA_VERSION, &version);
        text += std::string("; default model ") + name + " " + version;
        ssc_model_release(model);
    }
    return text + ")";
}

}  // namespace

#if !SSCAPE_WITH_TRAINING
namespace ssc::cli {
// Built without the training tools (SSCAPE_BUILD_TRAINING=OFF): the command exists and says so.
Run add_train(CLI::App& app) {
    CLI::App* c = app.add_subcommand("train", "train a model from the CC0 MakeHuman assets (not in this build)");
    c->allow_extras();
    return [] () -> int { throw std::runtime_error("this sscape was built without training (SSCAPE_BUILD_TRAINING=OFF)"); };
}
Run add_learn(CLI::App& app) {
    CLI::App* c = app.add_subcommand("learn", "learn a model from registered scans (not in this build)");
    c->allow_extras();
    return [] () -> int { throw std::runtime_error("this sscape was built without the learning tools (SSCAPE_BUILD_TRAINING=OFF)"); };
}
Run add_bootstrap(CLI::App& app) {
    CLI::App* c = app.add_subcommand("bootstrap", "learn a model from raw scans by rounds of registration and learning (not in this build)");
    c->allow_extras();
    return [] () -> int { throw std::runtime_error("this sscape was built without the learning tools (SSCAPE_BUILD_TRAINING=OFF)"); };
}
Run add_evaluate(CLI::App& app) {
    CLI::App* c = app.add_subcommand("evaluate", "measure shape spaces learned from registrations (not in this build)");
    c->allow_extras();
    return [] () -> int { throw std::runtime_error("this sscape was built without the learning tools (SSCAPE_BUILD_TRAINING=OFF)"); };
}
}  // namespace ssc::cli
#endif

namespace {

// " (did you mean 'X'?)" for the candidate nearest to a mistyped word (by edit distance, at most a
// third of its letters off, at least one), or "" when none is that near.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
    auto distance = [](const std::string& a, const std::string& b) {  // Levenshtein, two rows
        std::vector<std::size_t> row(b.size() + 1), next(b.size() + 1);
        for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
        for (std::size_t i = 1; i <= a.size(); ++i) {
            next[0] = i;
            for (std::size_t j = 1; j <= b.size(); ++j)
                next[j] = std::min({row[j] + 1, next[j - 1] + 1, row[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            std::swap(row, next);
        }
        return row[b.size()];
    };
    if (word.size() > 200) return "";  // no one mistypes that much; keeps the work bounded
    const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
    std::size_t best = limit + 1;
    std::string nearest;
    for (const auto& c : candidates) {
        const std::size_t d = distance(word, c);
        if (d < best) best = d, nearest = c;
    }
    return nearest.empty() ? "" : " (did you mean '" + nearest + "'?)";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"sscape: statistical 3D human body models (S-SCAPE): make bodies, fit them to landmarks, scans and "
                 "depth images, measure them, and train models. A MODEL is a .sscape file; commands that take one use "
                 "the default model built into the library when it is left out. Lengths are in metres.",
                 "sscape"};
    app.formatter(ssc::cli::help_formatter());
    app.set_version_flag("--version", version_text, "print the program, library and default model versions and exit");
    app.require_subcommand(1);
    app.failure_message([](const CLI::App* top, const CLI::Error& e) {
        const auto parsed = top->get_subcommands();  // the command being parsed, if it was named
        const std::string name = parsed.empty() ? "" : " " + parsed.front()->get_name();
        // An option nobody has: the command's option nearest to each, as a typo usually is.
        std::string hint;
        if (!parsed.empty() && dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
            std::vector<std::string> options;
            for (const CLI::Option* o : parsed.front()->get_options()) {
                for (const auto& l : o->get_lnames()) options.push_back("--" + l);
                for (const auto& s : o->get_snames()) options.push_back("-" + s);
            }
            // CLI11 names them after the message's colon ("...not expected: --seeed 3").
            const std::string what = e.what();
            std::istringstream words(what.substr(what.find(": ") == std::string::npos ? what.size() : what.find(": ") + 2));
            for (std::string extra; words >> extra;)
                if (extra.size() > 1 && extra[0] == '-') {
                    const std::string word = extra.substr(0, extra.find('='));
                    const std::string near = did_you_mean(word, options);
                    if (!near.empty()) hint += "\n'" + word + "'" + near;
                }
        }
        return "sscape" + name + ": " + e.what() + hint + "\nRun 'sscape" + (name.empty() ? " COMMAND" : name) + " --help' for the options.\n";
    });
    std::map<std::string, ssc::cli::Run> commands;
    for (const auto add : {ssc::cli::add_info, ssc::cli::add_synth, ssc::cli::add_measure, ssc::cli::add_fit, ssc::cli::add_register, ssc::cli::add_simulate,
                           ssc::cli::add_train, ssc::cli::add_learn, ssc::cli::add_bootstrap, ssc::cli::add_evaluate, ssc::cli::add_make_test_model}) {
        ssc::cli::Run run = add(app);
        commands[app.get_subcommands({}).back()->get_name()] = std::move(run);
    }
    app.footer("Example: sscape synth --random 5 -o out/body.glb\nRun 'sscape COMMAND --help' for a command's options.\n");  // after the commands: they would inherit it
    // Each command's help ends with examples a user can start from.
    const std::map<std::string, std::string> examples = {
        {"info", "sscape info\n  sscape info out/model.sscape --json"},
        {"synth", "sscape synth --random 5 --seed 1 -o out/body.glb\n  sscape synth --sliders stature=1.85,mass=80 --pose sitting -o out/body.obj"},
        {"measure", "sscape measure --shape 1,-0.5 --definitions\n  sscape measure --random 100 --csv out/measurements.csv\n"
                    "  sscape measure --mesh out/registered.ply --png out/measured.png"},
        {"fit", "sscape fit --points scan.ply --landmarks scan.lnd -o out/fit.glb --params out/fit.json"},
        {"register", "sscape register scan.ply --landmarks scan.lnd -o out/registered.ply --report out/registered.json --png out/registered.png"},
        {"simulate", "sscape simulate -o out/sim --seed 3 --depth front,back\n  sscape simulate --count 20 -o out/collection"},
        {"train", "sscape train --assets ../shared/makehuman -o out/model.sscape --report out/report_"},
        {"learn", "sscape learn registered/*.ply --components 20 -o out/learned.sscape"},
        {"bootstrap", "sscape bootstrap scans/ --rounds 3 -o out/bootstrap"},
        {"evaluate", "sscape evaluate registered/*.ply --posture none,skeleton -o out/evaluation"},
        {"make-test-model", "sscape make-test-model -o out/test.sscape --vertices 2000 --components 8"}};
    for (CLI::App* sub : app.get_subcommands({})) {
        const auto it = examples.find(sub->get_name());
        if (it != examples.end()) sub->footer("Example" + std::string(it->second.find('\n') == std::string::npos ? "" : "s") + ":\n  " + it->second + "\n");
    }
    // CLI11 reports an unknown command as a missing one; name it and the valid ones instead.
    if (argc >= 2 && argv[1][0] != '-' && !commands.count(argv[1])) {
        std::string names;
        std::vector<std::string> known;
        for (const auto& [name, run] : commands) names += (names.empty() ? "" : ", ") + name, known.push_back(name);
        std::fprintf(stderr, "sscape: unknown command '%s'%s; the commands: %s\nRun 'sscape --help' for what each does.\n", argv[1],
                     did_you_mean(argv[1], known).c_str(), names.c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);  // prints help, the version or the error
        return code == 0 ? 0 : 2;
    }
    const std::string name = app.get_subcommands().at(0)->get_name();
    try {
        return commands.at(name)();
    } catch (const ssc::cli::UsageError& e) {
        std::fprintf(stderr, "sscape %s: %s\nRun 'sscape %s --help' for the options.\n", name.c_str(), e.what(), name.c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sscape %s: %s\n", name.c_str(), e.what());
        return 1;
    }
}
