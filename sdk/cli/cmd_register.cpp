// `sscape register`: deforms the model's template onto a raw body scan through the C API
// (ssc_registration_run_file: the library reads the scan and writes the registered mesh in the
// model's topology, the JSON report beside it and optionally a picture of the scan beside the
// registration coloured by its distance to the scan).
#include "cli.hpp"
#include "progress.hpp"

#include <sscape/sscape_offline.h>

#include <cstdio>
#include <filesystem>
#include <memory>

namespace ssc::cli {
namespace {

struct Options {
    std::string scan, model, out, landmarks, png, report, units, up, start = "model", kernel = "thin-plate";
    bool constant = false, segments = true;  // add_register: the library's default
    double stiffness = 0;
};

int run_register(const Options& o) {
    if (o.out.size() < 4 || (o.out.substr(o.out.size() - 4) != ".obj" && o.out.substr(o.out.size() - 4) != ".ply"))
        throw UsageError("-o: the registered mesh is written as .obj or .ply");
    const std::string beside = std::filesystem::path(o.out).replace_extension(".json").string();
    if (!o.report.empty() && std::filesystem::path(o.report).lexically_normal() != std::filesystem::path(beside).lexically_normal())
        throw UsageError("--report: the report is written beside the mesh, as " + beside + " (where sscape learn reads it)");
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    ssc_registration_def def;
    ssc_registration_def_init(&def, sizeof def);
    def.start = o.start == "rigid" ? SSC_REGISTRATION_START_RIGID : o.start == "rbf" ? SSC_REGISTRATION_START_RBF : SSC_REGISTRATION_START_MODEL;
    def.schedule = o.constant ? SSC_REGISTRATION_CONSTANT : SSC_REGISTRATION_RELAXED;
    def.fit_segments = o.segments ? 1u : 0u;
    if (o.stiffness > 0) def.stiffness = float(o.stiffness);
    def.rbf_kernel = o.kernel == "gaussian" ? SSC_RBF_GAUSSIAN : o.kernel == "multiquadric" ? SSC_RBF_MULTIQUADRIC : SSC_RBF_THIN_PLATE;
    ssc_registration* reg = nullptr;
    check(ssc_registration_create(model, &def, &reg), "registration");
    std::unique_ptr<ssc_registration, void (*)(ssc_registration*)> owned(reg, ssc_registration_destroy);

    // The files, read and written by the library (the same job the Python pipeline runs per scan).
    ssc_scan_file_job job;
    ssc_scan_file_job_init(&job, sizeof job);
    job.scan_path = o.scan.c_str();
    job.landmarks_path = o.landmarks.empty() ? nullptr : o.landmarks.c_str();
    job.units = o.units.empty() ? nullptr : o.units.c_str();
    job.up = o.up.empty() ? nullptr : o.up.c_str();
    job.mesh_path = o.out.c_str();
    job.write_report = o.report.empty() ? 0 : 1;
    job.picture_path = o.png.empty() ? nullptr : o.png.c_str();

    ssc_registration_report report;
    report.struct_size = sizeof report;
    {
        Progress progress("register");
        const ssc_stage_progress_fn show = [](void* user, const char* stage, uint32_t done, uint32_t total) {
            char text[96];
            std::snprintf(text, sizeof text, "%s %u of %u", stage, done, total);
            return static_cast<Progress*>(user)->update(text) ? 0 : 1;
        };
        const ssc_status status = ssc_registration_run_file(reg, &job, show, &progress, &report, nullptr);
        if (status == SSC_ERROR_CANCELLED) {
            std::fprintf(stderr, "sscape register: cancelled (Ctrl-C); nothing written\n");
            return 130;
        }
        check(status, "registration");
    }
    const uint32_t V = ssc_model_vertex_count(model), T = ssc_model_triangle_count(model);
    std::printf("%s: %u points in %s\n", o.scan.c_str(), report.scan_points, o.units.empty() ? "m (the default; --units sets it)" : o.units.c_str());
    if (!o.landmarks.empty()) std::printf("%s: %u landmarks\n", o.landmarks.c_str(), report.landmarks);
    std::printf("registered in %.2f s (model fit %.2f s): %u rounds, %u solves; %u of %u vertices on the scan\n", report.seconds,
                report.fit_seconds, report.rounds, report.solves, report.valid_vertices, V);
    if (def.start == SSC_REGISTRATION_START_MODEL)
        std::printf("model fit: %s\n", def.fit_segments && ssc_model_segment_count(model) > 0 ? "whole-body components and segment shape spaces"
                                                                                             : "whole-body components only");
    const auto& q = report.quality;
    std::printf("scan to registration: mean %.2f mm, median %.2f mm, 95th percentile %.2f mm\n", q.scan_mean * 1e3, q.scan_median * 1e3,
                q.scan_p95 * 1e3);
    std::printf("vertices within 2 / 5 / 10 / 20 mm of the scan: %.0f / %.0f / %.0f / %.0f %%\n", 100 * q.within[0], 100 * q.within[1],
                100 * q.within[2], 100 * q.within[3]);
    std::printf("wrote %s (the model's %u vertices and %u triangles, in the scan's frame and units)\n", o.out.c_str(), V, T);
    if (!o.report.empty()) std::printf("wrote %s\n", beside.c_str());
    if (!o.png.empty()) std::printf("wrote %s\n", o.png.c_str());
    return 0;
}

}  // namespace

Run add_register(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand(
        "register", "deform the model's template onto a raw body scan, vertex for vertex (same vertex count and order as the model), "
                    "starting from the model fitted to the scan; writes the registered mesh and, on request, a report and a picture");
    c->add_option("SCAN", o->scan, "the scan: PLY or OBJ points or mesh (normals used where given, estimated elsewhere)")
        ->required()->type_name("SCAN.ply|.obj")->check(CLI::ExistingFile.description(""));
    add_model_argument(*c, o->model);
    c->add_option("-o,--output", o->out, "the registered mesh: OBJ or binary PLY, in the scan's frame and units")
        ->required()->type_name("OUT.obj|.ply");
    c->add_option("--landmarks", o->landmarks, "landmarks on the scan in the CAESAR .lnd format (millimetres unless --units), "
                                               "matched by name")
        ->type_name("FILE.lnd")->check(CLI::ExistingFile.description(""));
    c->add_option("--units", o->units, "units of the scan and landmark files (default: metres for the scan, millimetres for .lnd); "
                                       "inputs that would not span 5 cm to 3 m are refused")
        ->check(CLI::IsMember({"m", "cm", "mm"}).description(""))->type_name("m|cm|mm");
    c->add_option("--up", o->up, "the scan's up axis (default: found by the model fit, which tries every heading)")
        ->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z"}).description(""))->type_name("x|y|z|-x|-y|-z");
    c->add_option("--start", o->start, "where the deformation starts: the model fitted to the scan (default), the template "
                                       "aligned to the landmarks (rigid, 3 or more), or warped through them (rbf, 4 or more)")
        ->check(CLI::IsMember({"model", "rigid", "rbf"}).description(""))->type_name("model|rigid|rbf");
    c->add_option("--rbf-kernel", o->kernel, "the rbf start's kernel (default thin-plate)")
        ->check(CLI::IsMember({"thin-plate", "multiquadric", "gaussian"}).description(""))->type_name("thin-plate|multiquadric|gaussian");
    c->add_flag("--constant", o->constant, "keep the stiffness at its final value in every round instead of relaxing it");
    ssc_registration_def defaults;
    ssc_registration_def_init(&defaults, sizeof defaults);
    o->segments = defaults.fit_segments != 0;
    c->add_flag("--segments,!--no-segments", o->segments,
                "with --segments (the default) the model's segment shape spaces (arms, torso, legs) join its whole-body components "
                "in the model fit, for bodies whose proportions the whole body's cannot hold; --no-segments: the whole body's only "
                "(a little better on bodies the model holds)");
    c->add_option("--stiffness", o->stiffness, "the first round's stiffness (default 0.03)")->check(finite_in(1e-6, 1e6))->type_name("B");
    c->add_option("--report", o->report, "write the report as JSON beside the mesh (its path with .json, where sscape learn reads "
                                         "it): times, quality overall and per body region, the model fit, and per vertex whether it "
                                         "ended on the scan and its distance to it")
        ->type_name("OUT.json")->check(extension(".json"));
    c->add_option("--png", o->png, "draw the scan and the registration coloured by its distance to the scan, front and side")
        ->type_name("OUT.png")->check(extension(".png"));
    return [o] { return run_register(*o); };
}

}  // namespace ssc::cli
