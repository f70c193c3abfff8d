// `sscape register`: deforms the model's template onto a raw body scan through the C API
// registration and writes the registered mesh (the model's topology), a JSON report and optionally a
// picture of the scan beside the registration coloured by its distance to the scan.
#include "cli.hpp"
#include "progress.hpp"

#include "capi/cpp_access.hpp"
#include "common/rigid.hpp"
#include "export/mesh_writers.hpp"
#include "io/readers.hpp"
#include "render/registration_picture.hpp"
#include "synthesis/model.hpp"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cstdio>
#include <fstream>
#include <unordered_map>

namespace ssc::cli {
namespace {

struct Options {
    std::string scan, model, out, landmarks, png, report, units, up, start = "model", kernel = "thin-plate";
    bool constant = false;
    double stiffness = 0;
};

int run_register(const Options& o) {
    if (o.out.size() < 4 || (o.out.substr(o.out.size() - 4) != ".obj" && o.out.substr(o.out.size() - 4) != ".ply"))
        throw UsageError("-o: the registered mesh is written as .obj or .ply");
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    ssc_registration_def def;
    ssc_registration_def_init(&def, sizeof def);
    def.start = o.start == "rigid" ? SSC_REGISTRATION_START_RIGID : o.start == "rbf" ? SSC_REGISTRATION_START_RBF : SSC_REGISTRATION_START_MODEL;
    def.schedule = o.constant ? SSC_REGISTRATION_CONSTANT : SSC_REGISTRATION_RELAXED;
    if (o.stiffness > 0) def.stiffness = float(o.stiffness);
    def.rbf_kernel = o.kernel == "gaussian" ? SSC_RBF_GAUSSIAN : o.kernel == "multiquadric" ? SSC_RBF_MULTIQUADRIC : SSC_RBF_THIN_PLATE;
    ssc_registration* reg = nullptr;
    check(ssc_registration_create(model, &def, &reg), "registration");
    std::unique_ptr<ssc_registration, void (*)(ssc_registration*)> owned(reg, ssc_registration_destroy);

    // The scan, in metres and turned so that its up axis is +Y (undone on the result).
    const double to_metres = o.units.empty() ? 1.0 : units_to_metres(o.units);
    const Eigen::Matrix3d R = up_axis_rotation(o.up);
    const io::PointFile pf = io::read_points(o.scan);
    std::vector<Eigen::Vector3d> metres;
    for (const auto& p : pf.points) metres.push_back(R * (p * to_metres));
    const double span = check_body_size(o.scan, metres, o.units.empty() ? "m" : o.units, !o.units.empty());
    std::vector<float> pts, nrm;
    for (const auto& p : metres) pts.insert(pts.end(), {float(p.x()), float(p.y()), float(p.z())});
    for (const auto& n : pf.normals) {
        const Eigen::Vector3d r = R * n;
        nrm.insert(nrm.end(), {float(r.x()), float(r.y()), float(r.z())});
    }
    check(ssc_registration_set_scan(reg, pts.data(), nrm.empty() ? nullptr : nrm.data(), uint32_t(metres.size()), 0, nullptr, 0), o.scan);
    std::printf("%s: %zu points in %s, spanning %.2f m\n", o.scan.c_str(), metres.size(), o.units.empty() ? "m (the default; --units sets it)" : o.units.c_str(), span);
    if (!o.landmarks.empty()) {
        std::unordered_map<std::string, std::string> by_name;
        for (uint32_t l = 0; l < ssc_model_landmark_count(model); ++l) {
            const char* name = "";
            check(ssc_model_get_landmark_name(model, l, &name), "landmark name");
            by_name[io::normalized_landmark_name(name)] = name;
        }
        std::vector<std::string> names;
        std::vector<float> positions;
        std::vector<Eigen::Vector3d> marks;
        const double lnd_metres = o.units.empty() ? 1.0 : to_metres / 1e-3;  // read_lnd gives the format's millimetres as metres
        for (const auto& r : io::read_lnd(o.landmarks)) {
            const auto it = by_name.find(io::normalized_landmark_name(r.name));
            if (it == by_name.end()) {
                std::fprintf(stderr, "%s: landmark '%s' is not one of the model's; ignored\n", o.landmarks.c_str(), r.name.c_str());
                continue;
            }
            const Eigen::Vector3d p = R * (r.position * lnd_metres);
            names.push_back(it->second);
            marks.push_back(p);
            positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
        }
        check_body_size(o.landmarks, marks, o.units.empty() ? "mm" : o.units, !o.units.empty());
        std::vector<const char*> c_names;
        for (const auto& n : names) c_names.push_back(n.c_str());
        check(ssc_registration_set_landmarks_by_name(reg, c_names.data(), positions.data(), uint32_t(names.size())), o.landmarks);
        std::printf("%s: %zu landmarks\n", o.landmarks.c_str(), names.size());
    }

    ssc_registration_report report;
    report.struct_size = sizeof report;
    {
        Progress progress("register");
        const ssc_stage_progress_fn show = [](void* user, const char* stage, uint32_t done, uint32_t total) {
            char text[96];
            std::snprintf(text, sizeof text, "%s %u of %u", stage, done, total);
            return static_cast<Progress*>(user)->update(text) ? 0 : 1;
        };
        const ssc_status status = ssc_registration_run(reg, show, &progress, &report);
        if (status == SSC_ERROR_CANCELLED) {
            std::fprintf(stderr, "sscape register: cancelled (Ctrl-C); nothing written\n");
            return 130;
        }
        check(status, "registration");
    }
    const uint32_t V = ssc_model_vertex_count(model), T = ssc_model_triangle_count(model);
    std::printf("registered in %.2f s (model fit %.2f s): %u rounds, %u solves; %u of %u vertices on the scan\n", report.seconds,
                report.fit_seconds, report.rounds, report.solves, report.valid_vertices, V);
    const auto& q = report.quality;
    std::printf("scan to registration: mean %.2f mm, median %.2f mm, 95th percentile %.2f mm\n", q.scan_mean * 1e3, q.scan_median * 1e3,
                q.scan_p95 * 1e3);
    std::printf("vertices within 2 / 5 / 10 / 20 mm of the scan: %.0f / %.0f / %.0f / %.0f %%\n", 100 * q.within[0], 100 * q.within[1],
                100 * q.within[2], 100 * q.within[3]);

    std::vector<float> verts(3ull * V), distance(V);
    std::vector<uint8_t> valid(V);
    std::vector<uint32_t> tris(3ull * T);
    check(ssc_registration_get_vertices(reg, verts.data(), V, 0), "vertices");
    check(ssc_registration_get_valid(reg, valid.data(), V), "valid");
    check(ssc_registration_get_vertex_distances(reg, distance.data(), V), "distances");
    check(ssc_model_get_triangles(model, tris.data(), T), "triangles");
    std::vector<Eigen::Vector3d> registered(V);
    for (uint32_t v = 0; v < V; ++v) {
        registered[v] = Eigen::Vector3d(verts[3 * v], verts[3 * v + 1], verts[3 * v + 2]);
        const Eigen::Vector3d back = R.transpose() * registered[v] / to_metres;  // the scan's frame and units
        for (int a = 0; a < 3; ++a) verts[3 * v + std::size_t(a)] = float(back[a]);
    }
    exporters::MeshView mesh;
    mesh.vertex_count = V;
    mesh.positions = verts.data();
    mesh.triangle_count = T;
    mesh.triangles = tris.data();
    exporters::write_mesh(o.out, mesh);
    std::printf("wrote %s (the model's %u vertices and %u triangles, in the scan's frame and units)\n", o.out.c_str(), V, T);

    if (!o.report.empty()) {
        nlohmann::ordered_json j;
        j["scan"] = o.scan;
        // How the registered mesh's frame relates to the model's (sscape learn reads it back).
        j["scan_units_to_metres"] = to_metres;
        j["scan_up"] = o.up.empty() ? "y" : o.up;
        j["seconds"] = report.seconds;
        j["fit_seconds"] = report.fit_seconds;
        j["rounds"] = report.rounds;
        j["solves"] = report.solves;
        j["valid_vertices"] = report.valid_vertices;
        auto quality = [](const ssc_registration_quality& x) {
            return nlohmann::ordered_json{{"scan_to_registration_mean_m", x.scan_mean}, {"scan_to_registration_median_m", x.scan_median},
                                          {"scan_to_registration_p95_m", x.scan_p95},
                                          {"vertices_within_2_5_10_20_mm", {x.within[0], x.within[1], x.within[2], x.within[3]}}};
        };
        j["quality"] = quality(q);
        nlohmann::ordered_json regions = nlohmann::ordered_json::object();
        for (uint32_t r = 0; r < ssc_registration_region_count(reg); ++r) {
            const char* name = "";
            ssc_registration_quality rq;
            check(ssc_registration_get_region(reg, r, &name, &rq), "region");
            regions[name] = quality(rq);
        }
        j["regions"] = regions;
        if (def.start == SSC_REGISTRATION_START_MODEL) {
            const uint32_t K = ssc_model_shape_count(model), J = ssc_model_joint_count(model);
            std::vector<float> shape(K), rotations(4ull * J), translation(3);
            float scale = 1;
            check(ssc_registration_get_fit(reg, shape.data(), K, rotations.data(), J, translation.data(), &scale), "fit");
            j["fit"] = {{"shape", shape}, {"rotations_xyzw", rotations}, {"translation_m", translation}, {"scale", scale},
                        {"frame", "the scan's, turned so that --up is +Y, in metres"}};
        }
        j["valid"] = valid;
        std::ofstream f(o.report);
        f << j.dump(1) << "\n";
        if (!f) throw std::runtime_error("cannot write " + o.report);
        std::printf("wrote %s\n", o.report.c_str());
    }
    if (!o.png.empty()) {
        std::vector<double> error(V);
        for (uint32_t v = 0; v < V; ++v) error[v] = distance[v];
        // Drawn upright, facing the viewer when the fit found the body's heading (else as scanned).
        render::PictureFrame frame;
        if (def.start == SSC_REGISTRATION_START_MODEL) {
            const uint32_t J = ssc_model_joint_count(model);
            std::vector<float> rotations(4ull * J), translation(3);
            check(ssc_registration_get_fit(reg, nullptr, 0, rotations.data(), J, translation.data(), nullptr), "fit");
            fitting::FitState fit;
            for (uint32_t j = 0; j < J; ++j) fit.pose.emplace_back(rotations[4 * j + 3], rotations[4 * j], rotations[4 * j + 1], rotations[4 * j + 2]);
            fit.translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
            frame = render::fit_picture_frame(model_of(model), fit);
        }
        render::write_registration_picture(o.png, model_of(model), frame, metres, registered, error);
        std::printf("wrote %s\n", o.png.c_str());
    }
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
    c->add_option("--stiffness", o->stiffness, "the first round's stiffness (default 0.03)")->check(finite_in(1e-6, 1e6))->type_name("B");
    c->add_option("--report", o->report, "write the report as JSON: times, quality overall and per body region, the model fit, "
                                         "and per vertex whether it ended on the scan")
        ->type_name("OUT.json")->check(extension(".json"));
    c->add_option("--png", o->png, "draw the scan and the registration coloured by its distance to the scan, front and side")
        ->type_name("OUT.png")->check(extension(".png"));
    return [o] { return run_register(*o); };
}

}  // namespace ssc::cli
