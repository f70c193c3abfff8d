// `sscape fit`: fits the model to landmark files, point files and/or depth images through the C API
// fitter and writes the fitted mesh, a report and optionally a picture of the fit beside its input.
#include "cli.hpp"
#include "progress.hpp"

#include "capi/cpp_access.hpp"
#include "common/output_paths.hpp"
#include "export/body_export.hpp"
#include "export/mesh_writers.hpp"
#include "fitting/fitter.hpp"
#include "io/readers.hpp"
#include "io/units.hpp"
#include "render/fit_picture.hpp"

#include <sscape/sscape_offline.h>

#include <cstdio>

namespace ssc::cli {
namespace {

struct Options {
    std::string model, out, png, params;
    std::vector<std::string> landmarks, points, depth;
    std::string units;  // --units: m, cm or mm for every point and landmark file; empty: each format's default
    double units_scale = 1;  // --units to metres
    std::string intrinsics_text;
    std::vector<float> intrinsics;  // fx fy cx cy for depth images whose files do not give them
    bool scale = false, hands = false, frames = false;
    uint32_t components = 0, iterations = 0;
};

// What CLI11 cannot check: the combinations.
void finish(Options& o) {
    if (!o.intrinsics_text.empty()) {
        o.intrinsics = parse_floats(o.intrinsics_text, "--intrinsics");
        if (o.intrinsics.size() != 4) throw UsageError("--intrinsics needs FX,FY,CX,CY (pixels)");
    }
    if (!o.units.empty()) o.units_scale = io::units_to_metres(o.units);
    if (o.landmarks.empty() && o.points.empty() && o.depth.empty())
        throw UsageError("fit needs --landmarks FILE.lnd, --points FILE.ply|.obj and/or --depth FILE.pgm");
    exporters::format_of(o.out);  // refuses other extensions, naming the formats
}

// The files written (the bodies, parameters and picture; with --frames frame N's carry _frameN),
// none of them over an input.
std::vector<std::string> planned_outputs(const Options& o) {
    std::vector<std::string> inputs = {o.model};
    for (const auto* files : {&o.landmarks, &o.points, &o.depth}) inputs.insert(inputs.end(), files->begin(), files->end());
    std::vector<std::string> outputs = {o.png, o.params};
    for (std::size_t f = 0; f < inputs.size(); ++f) {  // with --frames, frame N's files carry _frameN
        for (const std::string& output : {o.out, o.png, o.params})
            if (!output.empty()) refuse_output_over_input(f == 0 ? output : with_suffix(output, "_frame" + std::to_string(f)), inputs);
        outputs.push_back(f == 0 ? o.out : with_suffix(o.out, "_frame" + std::to_string(f)));
    }
    return outputs;
}

// Landmark, point and depth files into the fitter: each file a frame of its own with --frames.
void add_inputs(const Options& o, ssc_fitter* fitter) {
    // Landmark and scan files are read by the library (ssc_fitter_add_*_file), as the Python
    // pipeline reads them; the picture shows what the fitter holds.
    // With --frames each file is a frame of its own (the person moved between them); otherwise all
    // observe one pose.
    uint32_t next_frame = 0;
    auto frame_for = [&]() { return o.frames ? next_frame++ : 0u; };
    auto file_def = [&](const std::string& path) {
        ssc_fit_file_def d;
        ssc_fit_file_def_init(&d, sizeof d);
        d.path = path.c_str();
        d.units = o.units.empty() ? nullptr : o.units.c_str();
        d.use_hands = o.hands;
        d.units_option = "--units";
        return d;
    };
    for (const auto& path : o.landmarks) {
        const uint32_t frame = frame_for();
        const ssc_fit_file_def d = file_def(path);
        ssc_fit_file_info info;
        info.struct_size = sizeof info;
        check(ssc_fitter_add_landmarks_file(fitter, frame, &d, &info), path);
        std::printf("%s: %u landmarks in %s%s, spanning %.2f m (%u hand landmarks left out; --hands uses them)\n", path.c_str(), info.used,
                    o.units.empty() ? "mm" : o.units.c_str(), o.units.empty() ? " (the .lnd convention; --units sets it)" : "", double(info.span),
                    info.left_out);
    }
    for (const auto& path : o.points) {
        const uint32_t frame = frame_for();
        const ssc_fit_file_def d = file_def(path);
        ssc_fit_file_info info;
        info.struct_size = sizeof info;
        check(ssc_fitter_add_points_file(fitter, frame, &d, &info), path);
        std::printf("%s: %u points in %s%s, spanning %.2f m; %u normals estimated\n", path.c_str(), info.used,
                    o.units.empty() ? "m" : o.units.c_str(), o.units.empty() ? " (the default; --units sets it)" : "", double(info.span),
                    info.left_out);
    }
    for (const auto& path : o.depth) {
        const io::DepthImage img = io::read_pgm_depth(path);
        ssc_depth_image_def def;
        ssc_depth_image_def_init(&def, sizeof def);
        def.width = img.width, def.height = img.height;
        def.format = SSC_DEPTH_F32_M;
        def.samples = img.depth.data();
        if (!o.intrinsics.empty()) def.fx = o.intrinsics[0], def.fy = o.intrinsics[1], def.cx = o.intrinsics[2], def.cy = o.intrinsics[3];
        else if (img.has_intrinsics) def.fx = float(img.fx), def.fy = float(img.fy), def.cx = float(img.cx), def.cy = float(img.cy);
        else throw UsageError(path + ": the file does not give the camera's intrinsics; pass --intrinsics FX,FY,CX,CY");
        float pose[16];
        for (int i = 0; i < 16; ++i) pose[i] = float(img.camera_to_world(i % 4, i / 4));
        if (img.has_pose) def.camera_to_world = pose;
        const uint32_t frame = frame_for();
        uint32_t added = 0;
        check(ssc_fitter_add_depth_image(fitter, frame, &def, &added), path);
        std::printf("%s: %u x %u depth image, %u points%s\n", path.c_str(), img.width, img.height, added,
                    img.has_pose ? "" : " (camera at the origin: the file gives no pose)");
    }
}

// Solves with a progress line (and a line per frame when there are several). CANCELLED on Ctrl-C.
ssc_status solve(ssc_fitter* fitter, ssc_fit_report& report) {
    const uint32_t frame_count = ssc_fitter_frame_count(fitter);
    Progress progress("fit");
    // Several frames: a line per frame as it is fitted.
    struct FrameLines {
        Progress* progress;
        uint32_t count;
    } lines{&progress, frame_count};
    const ssc_frame_fn frame_line = [](void* user, uint32_t frame, const ssc_fit_frame_report* r) {
        const auto* l = static_cast<const FrameLines*>(user);
        l->progress->clear();
        if (r->failed) std::printf("frame %u of %u: failed: %s\n", frame + 1, l->count, r->problem_text);
        else std::printf("frame %u of %u: fitted\n", frame + 1, l->count);
        std::fflush(stdout);
        return 0;
    };
    if (frame_count > 1) check(ssc_fitter_set_frame_callback(fitter, frame_line, &lines), "fit");
    const ssc_progress_fn show = [](void* user, uint32_t iteration, float cost) {
        char text[96];
        std::snprintf(text, sizeof text, "iteration %u, cost %.4g", iteration, double(cost));
        return static_cast<Progress*>(user)->update(text) ? 0 : 1;
    };
    return ssc_fitter_solve(fitter, show, &progress, &report);
}

// Says how the fit went; 1 when it failed as a whole (nothing is written), else 0.
int judge(const Options& o, const ssc_fit_report& report, const std::vector<ssc_fit_frame_report>& frame_reports) {
    const uint32_t frame_count = uint32_t(frame_reports.size());
    const char* outcome = report.converged ? "converged" : report.implausible ? "failed" : "iteration limit";
    std::printf("fit: %u iterations, %s, %.1f ms; cost %.4g -> %.4g\n", report.iterations, outcome,
                report.seconds * 1e3, report.initial_cost, report.final_cost);
    if (report.restarts) std::printf("restarts: %u (a fit from a start was judged wrong and redone from another)\n", report.restarts);
    if (!o.landmarks.empty()) std::printf("landmark rms distance: %.2f mm\n", report.landmark_rms * 1e3);
    if (!o.points.empty() || !o.depth.empty())
        std::printf("points: mean correspondence distance %.2f mm, inliers %.1f %%, %.1f %% on a surface farther than 5 cm from the fit\n",
                    report.point_mean * 1e3, 100 * report.inlier_fraction, 100 * report.unexplained_fraction);
    if (frame_count == 1 && frame_reports[0].unscanned[0]) std::printf("note: %s\n", frame_reports[0].unscanned);
    if (frame_count == 1 && report.implausible && report.unexplained_fraction >= SSC_FIT_UNEXPLAINED_LIMIT) {
        // Much of the scan off the body: its text says what may be in the scan besides the person.
        std::fprintf(stderr, "sscape fit: failed: %s (after %u restart(s)); nothing written\n", frame_reports[0].problem_text, report.restarts);
        return 1;
    }
    if (frame_count == 1 && report.implausible) {
        std::fprintf(stderr,
                     "sscape fit: failed: %s (after %u restart(s)): a limb or the whole body is most likely in the wrong place "
                     "(a hard pose: try adding landmarks with --landmarks); nothing written\n",
                     frame_reports[0].problem_text, report.restarts);
        return 1;
    }
    if (frame_count > 1 && report.failed_frames == frame_count) {
        std::fprintf(stderr, "sscape fit: failed: no frame found its person (frame 1: %s); nothing written\n", frame_reports[0].problem_text);
        return 1;
    }
    return 0;
}

// The fit's scale, translation and shape on stdout.
void print_solution(ssc_model* model, ssc_fitter* fitter) {
    const uint32_t J = ssc_model_joint_count(model), K = ssc_model_shape_count(model);
    std::vector<float> shape(K), rotations(4ull * J), translation(3);
    float scale = 1;
    check(ssc_fitter_get_shape(fitter, shape.data(), K), "shape");
    check(ssc_fitter_get_pose(fitter, 0, rotations.data(), J, translation.data(), &scale), "pose");
    std::printf("scale %.4f, translation %.3f %.3f %.3f m\nshape:", scale, translation[0], translation[1], translation[2]);
    for (uint32_t k = 0; k < K; ++k) std::printf("%s%.3f", k ? "," : " ", shape[k]);
    std::printf("\n");
}

// Each frame's result as a body (shape, pose, translation), written by the library: OBJ and PLY
// with normals (OBJ with UVs), glTF rigged. A fitted scale is no part of a body: those fits are
// written as meshes from the fitter's vertices. A failed frame is never written: its pose is not
// to be trusted.
void write_frames(const Options& o, ssc_model* model, ssc_fitter* fitter, const std::vector<ssc_fit_frame_report>& frame_reports) {
    const uint32_t V = ssc_model_vertex_count(model), T = ssc_model_triangle_count(model), J = ssc_model_joint_count(model);
    const uint32_t K = ssc_model_shape_count(model), F = ssc_fitter_frame_count(fitter);
    std::vector<float> shape(K), vertices(3ull * V), rotations(4ull * J), translation(3);
    std::vector<uint32_t> triangles(3ull * T);
    check(ssc_fitter_get_shape(fitter, shape.data(), K), "shape");
    check(ssc_model_get_triangles(model, triangles.data(), T), "triangles");
    for (uint32_t f = 0; f < F; ++f) {
        const std::string path = f == 0 ? o.out : with_suffix(o.out, "_frame" + std::to_string(f));
        if (frame_reports[f].failed) {
            std::printf("frame %u of %u failed (%s): left out of the shared shape, %s not written\n", f + 1, F,
                        frame_reports[f].problem_text, path.c_str());
            continue;
        }
        float scale = 1;
        check(ssc_fitter_get_pose(fitter, f, rotations.data(), J, translation.data(), &scale), "pose");
        if (scale == 1.0f) {
            Handles out_body(nullptr);
            check(ssc_body_create(model, nullptr, &out_body.body), "body");
            check(ssc_body_set_shape(out_body.body, shape.data(), K), "shape");
            check(ssc_body_set_pose(out_body.body, rotations.data(), J, translation.data()), "pose");
            check(ssc_body_write_file(out_body.body, path.c_str(), SSC_FILE_FORMAT_BY_EXTENSION), path);
        } else {
            if (exporters::format_of(path) == exporters::BodyFormat::Glb)
                throw std::runtime_error(path + ": a fit with a fitted scale (--scale) is written as .obj or .ply, not as a rigged body");
            check(ssc_fitter_get_vertices(fitter, f, vertices.data(), V, 0), "vertices");
            exporters::MeshView mesh;
            mesh.vertex_count = V;
            mesh.positions = vertices.data();
            mesh.triangle_count = T;
            mesh.triangles = triangles.data();
            exporters::write_mesh(path, mesh);
        }
        std::printf("wrote %s\n", path.c_str());
    }
}

// Frame 0's input as the fitter holds it (landmarks, points, depth images' points), then the fit.
void write_picture(const std::string& png, ssc_model* model, ssc_fitter* fitter) {
    const fitting::Fitter& solved = fitter_of(fitter);
    const fitting::Frame& input = solved.frame(0);
    std::vector<Eigen::Vector3d> shown;
    for (const auto& l : input.landmarks) shown.push_back(l.position);
    for (const auto& cloud : input.clouds) shown.insert(shown.end(), cloud.points.begin(), cloud.points.end());
    render::write_fit_picture(png, model_of(model), solved.frame_state(0), shown, solved.vertices(0), {});
    std::printf("wrote %s (input, then the fit; front and side)\n", png.c_str());
}

int run_fit(Options o) {
    finish(o);
    // The bodies, the parameters and the picture: an unwritable one refused before the fit, and a
    // write that fails leaves none of them (an unwritable --params once left the body).
    OutputFiles written(planned_outputs(o));
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    ssc_fitter_def def;
    ssc_fitter_def_init(&def, sizeof def);
    def.fit_scale = o.scale;
    def.shape_count = o.components;
    if (o.iterations) def.max_iterations = o.iterations;
    check(ssc_fitter_create(model, &def, &guard.fitter), "fitter");
    add_inputs(o, guard.fitter);
    ssc_fit_report report;
    report.struct_size = sizeof report;
    const ssc_status status = solve(guard.fitter, report);
    if (status == SSC_ERROR_CANCELLED) {
        std::fprintf(stderr, "sscape fit: cancelled (Ctrl-C); nothing written\n");
        return 130;
    }
    check(status, "fit");
    const uint32_t frame_count = ssc_fitter_frame_count(guard.fitter);
    std::vector<ssc_fit_frame_report> frame_reports(frame_count);
    for (uint32_t f = 0; f < frame_count; ++f) {
        frame_reports[f].struct_size = sizeof(ssc_fit_frame_report);
        check(ssc_fitter_get_frame_report(guard.fitter, f, &frame_reports[f]), "fit");
    }
    if (judge(o, report, frame_reports) != 0) return 1;
    print_solution(model, guard.fitter);
    write_frames(o, model, guard.fitter, frame_reports);
    if (!o.params.empty()) {  // the fit's parameters, for `sscape synth --params` and for scripts
        check(ssc_fitter_write_params(guard.fitter, &report, o.params.c_str()), o.params);
        std::printf("wrote %s (shape, segment coefficients, per-joint rotations, translation, scale and the report)\n", o.params.c_str());
    }
    if (!o.png.empty()) write_picture(o.png, model, guard.fitter);
    written.keep();  // failed frames were never written; the others stay, as said below
    if (report.failed_frames > 0) {
        std::fprintf(stderr, "sscape fit: %u of %u frames failed (listed above) and were not written; the other %u were\n",
                     report.failed_frames, frame_count, frame_count - report.failed_frames);
        return 1;
    }
    return 0;
}

}  // namespace

Run add_fit(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand(
        "fit", "fit the model's shape and pose to landmarks, scans and/or depth images and write the fitted body; exits 1, writing "
               "nothing, when the fit is judged wrong (a joint past its range, the scan unexplained, a limb where the scan saw "
               "empty space); with --frames, exits 1 when a frame failed, writing every other frame");
    add_model_argument(*c, o->model);
    c->add_option("--landmarks", o->landmarks, "landmarks in the CAESAR .lnd format (millimetres unless --units), matched by name; "
                                               "repeat for more files")
        ->type_name("FILE.lnd")->allow_extra_args(false)->check(CLI::ExistingFile.description(""));
    c->add_option("--points", o->points, "a scan: PLY or OBJ points (normals used where given, estimated where missing or zero; "
                                         "metres unless --units); repeat for more files")
        ->type_name("FILE.ply|.obj")->allow_extra_args(false)->check(CLI::ExistingFile.description(""));
    c->add_option("--depth", o->depth, "a depth image: 16-bit PGM in millimetres, its camera in the header (or --intrinsics); "
                                       "repeat for more cameras")
        ->type_name("FILE.pgm")->allow_extra_args(false)->check(CLI::ExistingFile.description(""));
    c->add_option("-o,--output", o->out, "the fitted body: OBJ (normals, UVs), binary PLY or rigged glTF; with --frames, frame N "
                                         "goes to OUT_frameN.EXT")
        ->required()->type_name("OUT.obj|.ply|.glb");
    c->add_option("--units", o->units, "units of every point and landmark file (default: metres for scans, millimetres for .lnd); "
                                       "inputs that would not span 5 cm to 3 m are refused")
        ->check(CLI::IsMember({"m", "cm", "mm"}).description(""))->type_name("m|cm|mm");
    c->add_option("--intrinsics", o->intrinsics_text, "the depth camera's focal lengths and centre in pixels, for files that do "
                                                      "not give them")
        ->type_name("FX,FY,CX,CY");
    c->add_flag("--frames", o->frames, "each file is a frame of its own (the person moved between them); one shared shape, a pose "
                                       "per frame");
    c->add_flag("--scale", o->scale, "also fit a uniform scale (written as .obj or .ply only: a body has no scale)");
    c->add_flag("--hands", o->hands, "use the hand landmarks too (left out by default: scanned hands are rarely posed like the "
                                     "model's)");
    c->add_option("--components", o->components, "shape components fitted (default: all)")->type_name("K");
    c->add_option("--iterations", o->iterations, "iteration limit of the solver")->check(CLI::Range(1u, 100000u))->type_name("N");
    c->add_option("--png", o->png, "draw the input and the fit, front and side")->type_name("OUT.png")->check(extension(".png"));
    c->add_option("--params", o->params, "write the shape, per-joint rotations, translation, scale and the report as JSON "
                                         "(sscape synth --params reads it back)")
        ->type_name("OUT.json");
    return [o] { return run_fit(*o); };
}

}  // namespace ssc::cli
