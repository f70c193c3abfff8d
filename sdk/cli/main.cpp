// `sscape`: the command line. Assembles the commands (one file each) into one CLI11 app, runs the
// one named and maps failures to exit codes: 0 done, 1 failed (a file, the library, a fit that did
// not explain its scan), 2 a usage error, 130 cancelled with Ctrl-C.
#include "cli.hpp"

#include <cstdio>
#include <exception>
#include <map>

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
Run add_register(CLI::App& app) {
    CLI::App* c = app.add_subcommand("register", "deform the model's template onto a raw body scan (not in this build)");
    c->allow_extras();
    return [] () -> int { throw std::runtime_error("this sscape was built without the offline tools (SSCAPE_BUILD_TRAINING=OFF)"); };
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
        return "sscape" + name + ": " + e.what() + "\nRun 'sscape" + (name.empty() ? " COMMAND" : name) + " --help' for the options.\n";
    });
    std::map<std::string, ssc::cli::Run> commands;
    for (const auto add : {ssc::cli::add_info, ssc::cli::add_synth, ssc::cli::add_measure, ssc::cli::add_fit, ssc::cli::add_register, ssc::cli::add_simulate,
                           ssc::cli::add_train, ssc::cli::add_learn, ssc::cli::add_bootstrap, ssc::cli::add_evaluate, ssc::cli::add_make_test_model}) {
        ssc::cli::Run run = add(app);
        commands[app.get_subcommands({}).back()->get_name()] = std::move(run);
    }
    app.footer("Run 'sscape COMMAND --help' for a command's options.");  // after the commands: they would inherit it
    // CLI11 reports an unknown command as a missing one; name it and the valid ones instead.
    if (argc >= 2 && argv[1][0] != '-' && !commands.count(argv[1])) {
        std::string names;
        for (const auto& [name, run] : commands) names += (names.empty() ? "" : ", ") + name;
        std::fprintf(stderr, "sscape: unknown command '%s'; the commands: %s\nRun 'sscape --help' for what each does.\n", argv[1],
                     names.c_str());
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
