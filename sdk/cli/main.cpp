#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <stdexcept>

namespace ssc::cli {

void check(ssc_status status, const std::string& what) {
    if (status != SSC_OK)
        throw std::runtime_error(what + ": " + ssc_status_name(status) + ": " + ssc_last_error());
}

std::vector<float> parse_floats(const std::string& text, const std::string& option) {
    std::vector<float> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        errno = 0;
        const float v = std::strtof(item.c_str(), &end);
        if (item.empty() || *end != '\0' || errno || !std::isfinite(v))
            throw UsageError(option + ": '" + item + "' is not a finite number");
        out.push_back(v);
    }
    if (out.empty()) throw UsageError(option + " needs comma-separated numbers");
    return out;
}

uint32_t parse_count(const std::string& text, const std::string& option) {
    char* end = nullptr;
    errno = 0;
    const unsigned long v = std::strtoul(text.c_str(), &end, 10);
    if (text.empty() || text[0] == '-' || *end != '\0' || errno || v > 0xFFFFFFFFul)
        throw UsageError(option + ": '" + text + "' is not a non-negative integer");
    return static_cast<uint32_t>(v);
}

const std::string& option_value(const std::vector<std::string>& args, std::size_t& i) {
    if (i + 1 >= args.size()) throw UsageError(args[i] + " needs a value");
    return args[++i];
}

std::string with_suffix(const std::string& path, const std::string& suffix) {
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos) return path + suffix;
    return path.substr(0, dot) + suffix + path.substr(dot);
}

ssc_model* load_model(const std::string& path) {
    ssc_model* model = nullptr;
    if (path.empty()) check(ssc_model_load_default(nullptr, &model), "cannot load the default model");
    else check(ssc_model_load_file(nullptr, path.c_str(), &model), "cannot load '" + path + "'");
    return model;
}

}  // namespace ssc::cli

namespace {

const char* kUsage =
    "usage: sscape <command> [options]\n"
    "MODEL is a .sscape file; without one, the default model built into the library is used.\n"
    "commands:\n"
    "  info [MODEL] [--json]      counts, metadata, joint names, sliders, component standard deviations, file size\n"
    "  synth [MODEL] -o OUT.obj|.ply|.glb [--shape C1,C2,...] [--pose NAME|JOINT=AX,AY,AZ;...]\n"
    "        [--translation X,Y,Z] [--random N [--seed S]] [--params FIT.json] [--png VIEW.png] [--landmarks-png LM.png]\n"
    "        [--limits clamp|reject]\n"
    "        [--sliders stature=1.85,mass=80,...] [--measure stature=1.7,waist_girth=0.8,... [--sex male|female] [--age Y]]\n"
    "                             write posed bodies; with --random N, N random shapes to OUT_000.obj ...;\n"
    "                             named poses: a_pose (rest), t_pose, sitting, arms_raised, crouching, kneeling,\n"
    "                             bending_forward, bent_over_arms_raised, lunge, arms_behind_back; --sliders sets\n"
    "                             semantic sliders, --measure makes the body to measure (SI units);\n"
    "                             --landmarks-png draws the first body's 73 landmarks\n"
    "  make-test-model -o OUT.sscape [--vertices N] [--components K] [--skeleton humanoid|mini] [--seed S]\n"
    "                             write a procedural test model\n"
    "  train --assets MAKEHUMAN_DIR -o OUT.sscape [--bodies N] [--components K] [--seed S]\n"
    "        [--heldout N] [--population-csv FILE] [--report PREFIX] [--procrustes]\n"
    "                             train a model from the CC0 MakeHuman assets\n"
    "  fit [MODEL] (--landmarks FILE.lnd | --points FILE.ply|.obj | --depth FILE.pgm)... -o OUT.obj|.ply|.glb\n"
    "      [--units m|cm|mm] [--intrinsics FX,FY,CX,CY] [--frames] [--scale] [--hands] [--components K]\n"
    "      [--iterations N] [--png FIT.png] [--params FIT.json]\n"
    "                             fit shape and pose to landmarks, scans and/or depth images; write the\n"
    "                             fitted body (.glb: rigged; --frames: each file is its own frame, one shared\n"
    "                             shape) and with --params its parameters, which synth --params reads\n"
    "  simulate [MODEL] -o PREFIX [--seed S] [--points N] [--noise M] [--missing F] [--outliers F]\n"
    "      [--landmark-noise M] [--pose-amount A] [--heading DEG] [--depth front|back|front,back]\n"
    "      [--depth-noise M]\n"
    "                             a random posed body measured: PREFIX_scan.ply, PREFIX.lnd, PREFIX_truth.obj,\n"
    "                             with --depth PREFIX_front.pgm / PREFIX_back.pgm (16-bit mm, camera in header)\n"
    "  measure [MODEL] [--shape C1,C2,...] [--random N [--seed S]] [--csv OUT.csv] [--png PATHS.png]\n"
    "      [--definitions] [--json]\n"
    "                             body measurements (stature, girths, lengths, area, volume, mass) of a\n"
    "                             shape; --png draws where each is taken on the first body\n";

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    try {
        if (command == "info") return ssc::cli::cmd_info(args);
        if (command == "synth") return ssc::cli::cmd_synth(args);
        if (command == "make-test-model") return ssc::cli::cmd_make_test_model(args);
#if SSCAPE_WITH_TRAINING
        if (command == "train") return ssc::cli::cmd_train(args);
#else
        if (command == "train") throw std::runtime_error("this sscape was built without training (SSCAPE_BUILD_TRAINING=OFF)");
#endif
        if (command == "fit") return ssc::cli::cmd_fit(args);
        if (command == "simulate") return ssc::cli::cmd_simulate(args);
        if (command == "measure") return ssc::cli::cmd_measure(args);
        throw ssc::cli::UsageError("unknown command '" + command + "'");
    } catch (const ssc::cli::UsageError& e) {
        std::fprintf(stderr, "sscape: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sscape: %s\n", e.what());
        return 1;
    }
}
