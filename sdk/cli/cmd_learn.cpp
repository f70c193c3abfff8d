// `sscape learn`: a model from registered scans (what `sscape register` writes: the mesh, and its
// --report JSON beside it with the same name), through learning::learn_model. An offline tool like
// `sscape train`: it links the C++ learning library.
#include "cli.hpp"

#include "capi/cpp_access.hpp"
#include "common/error.hpp"
#include "common/output_paths.hpp"
#include "io/readers.hpp"
#include "learning/learn_model.hpp"
#include "scan_files/registration_record.hpp"
#include "learning/scan_tables.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace ssc::cli {
namespace {

struct Options {
    std::vector<std::string> registrations;
    std::string model, out, posture = "skeleton", attributes, name = "sscape-learned", license;
    uint32_t components = 20, segment_components = 0, threads = 0;
    bool scale = false;
    double segment_band_mm = 80;
};

std::string stem_of(const std::string& path) { return std::filesystem::path(path).stem().string(); }

int run_learn(const Options& o) {
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    std::vector<std::string> inputs = {o.model, o.attributes};
    for (const auto& path : o.registrations) inputs.push_back(path), inputs.push_back(scan_files::record_report_path(path));
    refuse_output_over_input(o.out, inputs);
    ssc_model* handle = load_model(o.model);
    Handles guard(handle);
    const Model& model = model_of(handle);
    learning::LearnSpec spec;
    spec.components = o.components;
    spec.posture = learning::posture_from_name(o.posture);
    spec.segment_components = o.segment_components;
    spec.scale = o.scale;
    spec.segment_band = o.segment_band_mm * 1e-3;
    spec.threads = o.threads;
    spec.name = o.name;
    if (!o.license.empty()) spec.license = o.license;
    if (o.registrations.size() <= o.components)
        throw UsageError("--components " + std::to_string(o.components) + " needs more than that many registrations (" +
                         std::to_string(o.registrations.size()) + " given)");
    std::vector<scan_files::RegisteredScan> scans;
    for (const auto& path : o.registrations) scans.push_back(scan_files::read_registration_record(path, model, spec.posture == learning::Posture::Skeleton).registered);
    if (!o.attributes.empty()) {
        std::vector<std::string> stems;
        for (const auto& path : o.registrations) stems.push_back(stem_of(path));
        spec.attributes = learning::attributes_for(learning::read_attribute_table(o.attributes), stems);
    }
    std::ostringstream prov;
    prov << "registrations:";
    for (const auto& path : o.registrations) prov << " " << std::filesystem::path(path).filename().string();
    if (!o.attributes.empty()) prov << "\nattributes: " << std::filesystem::path(o.attributes).filename().string();
    spec.provenance = prov.str();
    learning::LearnReport report;
    const format::ModelData learned = learning::learn_model(model.data(), scans, spec, &report, [&](const std::string& stage) {
        std::printf("[%6.1f s] %s\n", elapsed(), stage.c_str());
        std::fflush(stdout);
    });
    const std::vector<unsigned char> bytes = format::write_model(learned);
    format::write_file(o.out, bytes);
    std::printf("wrote %s: %zu bytes, %u components from %u registrations (posture normalization %s), in %.1f s\n", o.out.c_str(), bytes.size(),
                report.components, report.bodies, learning::posture_name(spec.posture), elapsed());
    std::printf("the components hold %.1f %% of the registrations' variance; 1 SD moves a vertex by (RMS, mm):", 100 * report.explained);
    for (std::size_t k = 0; k < std::min<std::size_t>(8, report.stddev.size()); ++k)
        std::printf(" %.1f", report.stddev[k] / std::sqrt(double(model.vertex_count())) * 1e3);
    std::printf("%s\n", report.stddev.size() > 8 ? " ..." : "");
    std::printf("basis quantization: worst vertex error %.4f mm with every component at +-3 SD\n", report.quantization_error * 1e3);
    std::printf("attributes: %zu measured, %zu given; sliders:", learned.attributes.attributes.size() - spec.attributes.size(), spec.attributes.size());
    for (const auto& name : report.sliders) std::printf(" %s", name.c_str());
    if (!report.not_sliders.empty()) {
        std::printf("; attributes only (dependent on the sliders before them in this collection):");
        for (const auto& name : report.not_sliders) std::printf(" %s", name.c_str());
    }
    std::printf("\n");
    print_segment_compactness(report.segments);
    return 0;
}

}  // namespace

Run add_learn(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("learn", "learn a model from registered scans (sscape register's meshes, each with its --report JSON beside it)");
    c->add_option("registrations", o->registrations, "registered meshes (.ply or .obj) in the model's topology; REG.json beside each")
        ->required()
        ->check(CLI::ExistingFile);
    c->add_option("--model", o->model, "the model the scans were registered with (default: the built-in model)")->check(CLI::ExistingFile);
    c->add_option("-o,--output", o->out, "the learned model (.sscape)")->required()->check(extension(".sscape"));
    c->add_option("--components", o->components, "shape components to keep (default 20; fewer than the registrations)")
        ->check(CLI::Range(1u, 1000u));
    c->add_option("--posture", o->posture, "posture normalization before PCA: skeleton (default: each scan's fitted skinning undone), "
                                    "laplacian (rebuilt at rest from posture-free coordinates; no fit needed) or none")
        ->check(CLI::IsMember(kPostureNames));
    c->add_flag("--scale", o->scale, "Procrustes alignment with scale: every body brought to the collection's average size, so the "
                                     "model holds proportions only (no stature)");
    c->add_option("--segment-components", o->segment_components,
                  "also learn a shape space per body segment (head, arms, torso, legs) with this many components each (default 0: none)")
        ->check(CLI::Range(0u, 1000u));
    c->add_option("--segment-band", o->segment_band_mm, "millimetres on each side of a segment border over which segments blend (default 80)")
        ->check(CLI::Range(5.0, 500.0));
    c->add_option("--attributes", o->attributes, "CSV of known attributes: a header scan,NAME,..., one row per registration named by its file stem")
        ->check(CLI::ExistingFile);
    c->add_option("--name", o->name, "the model's name in its metadata (default sscape-learned)");
    c->add_option("--license", o->license, "the learned model's licence, the scans' owner's to give (default: unspecified)");
    c->add_option("--threads", o->threads, "worker threads of the posture normalization (default: all)")->check(CLI::Range(0u, 256u));
    return [o] { return run_learn(*o); };
}

}  // namespace ssc::cli
