// sscape measure: the body measurements of one shape or of random shapes, as a table, CSV (SI
// units) and a picture of where they are taken.
#include "body_inputs.hpp"
#include "cli.hpp"
#include "progress.hpp"

#include "capi/cpp_access.hpp"
#include "common/files.hpp"
#include "io/readers.hpp"
#include "io/units.hpp"
#if SSCAPE_WITH_TRAINING
#include "learning/posture_normalization.hpp"
#include "scan_files/registration_record.hpp"
#endif
#include "measure/measurements.hpp"
#include "measure/mesh_body.hpp"
#include "render/measure_picture.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

namespace ssc::cli {
namespace {

struct Options {
    std::string model, csv, png, params, mesh, units;
    std::string shape_text, sliders_text;
    std::vector<float> shape;
    std::vector<std::pair<std::string, float>> sliders;
    uint32_t random = 0, seed = 1;
    bool definitions = false, json = false;
};

// Display units: centimetres, square metres, litres, kilograms.
struct Shown {
    double factor;
    const char* unit;
};
Shown shown(ssc_unit u) {
    switch (u) {
        case SSC_UNIT_METRE: return {100, "cm"};
        case SSC_UNIT_SQUARE_METRE: return {1, "m2"};
        case SSC_UNIT_CUBIC_METRE: return {1000, "L"};
        default: return {1, "kg"};
    }
}

const char* si_unit(ssc_unit u) {
    switch (u) {
        case SSC_UNIT_METRE: return "m";
        case SSC_UNIT_SQUARE_METRE: return "m2";
        case SSC_UNIT_CUBIC_METRE: return "m3";
        default: return "kg";
    }
}

// --mesh: the file's vertices in metres, in the model's frame at rest where its registration report
// says how (the model fit's posture undone); else as the file has them. Says which on stdout.
std::vector<Eigen::Vector3d> read_mesh(ssc_model* model, const Options& o) {
    const std::string report = std::filesystem::path(o.mesh).replace_extension(".json").string();  // where register --report puts it
    nlohmann::json j;
    if (std::filesystem::is_regular_file(report)) j = nlohmann::json::parse(read_regular_file(report, 256u << 20), nullptr, false);
    if (j.is_object() && j.contains("scan_units_to_metres")) {  // `sscape register --report` wrote it
#if !SSCAPE_WITH_TRAINING
        throw std::runtime_error(report + " is a registration's report, which this sscape cannot read (built without the offline tools)");
#else
        if (!o.units.empty()) throw UsageError("--units: " + report + " gives the registration's units; leave --units out");
        const scan_files::RegistrationRecord r = scan_files::read_registration_record(o.mesh, model_of(model), false);
        if (!r.registered.has_fit) {
            std::printf("mesh: %s, its registration in the scan's posture (the report has no model fit to undo it)\n", o.mesh.c_str());
            return r.registered.vertices;
        }
        std::printf("mesh: %s, brought to rest with its registration's model fit (%s)\n", o.mesh.c_str(), report.c_str());
        return learning::unpose_skeleton(model_of(model), r.registered.fit, r.registered.vertices);
#endif
    }
    const double to_metres = io::units_to_metres(o.units.empty() ? "m" : o.units);
    std::vector<Eigen::Vector3d> v = io::read_points(o.mesh).points;
    for (Eigen::Vector3d& p : v) p *= to_metres;
    io::checked_body_span(o.mesh, v, to_metres, !o.units.empty(), "--units");
    std::printf("mesh: %s, measured in the posture it has\n", o.mesh.c_str());
    return v;
}

int run_measure(Options o) {
    if (!o.shape_text.empty()) o.shape = parse_floats(o.shape_text, "--shape");
    if (!o.sliders_text.empty()) o.sliders = parse_named(o.sliders_text, "--sliders");
    if (!o.units.empty() && o.mesh.empty()) throw UsageError("--units goes with --mesh");
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    const uint32_t K = ssc_model_shape_count(model), M = ssc_measurement_count();
    if (o.shape.size() > K) throw UsageError("--shape has " + std::to_string(o.shape.size()) + " values; the model has " + std::to_string(K) + " components");
    if (!o.params.empty()) {
        o.shape = read_params(model, o.params).shape;  // measured at rest: the fit's pose does not matter
        if (o.shape.size() > K) throw UsageError(o.params + ": its shape has " + std::to_string(o.shape.size()) + " values; the model has " + std::to_string(K));
    }
    std::vector<const char*> names(M), definitions(M);
    std::vector<ssc_unit> units(M);
    for (uint32_t m = 0; m < M; ++m) check(ssc_measurement_get_info(m, &names[m], &units[m], &definitions[m]), "measurement info");
    check(ssc_body_create(model, nullptr, &guard.body), "body");
    measure::MeshBody mesh;
    if (!o.mesh.empty()) {
        mesh = measure::mesh_body(model_of(model), read_mesh(model, o));
        std::printf("mesh: %.1f mm from the model's nearest body (root mean square)%s\n", 1000 * mesh.off_shape_space,
                    mesh.off_shape_space > measure::kFarFromShapeSpace ? "; far: a posed body or another mesh's vertices give wrong figures" : "");
    }

    // Random shapes as sscape synth --random draws them (truncated at 2.5 SD).
    std::vector<float> random(std::size_t(o.random) * K);
    if (o.random) check(ssc_model_sample_shapes(model, o.seed, o.random, 2.5f, random.data(), uint32_t(random.size())), "random shapes");
    const uint32_t n = o.random ? o.random : 1;
    std::ostringstream csv;
    csv << "body";
    for (uint32_t m = 0; m < M; ++m) csv << "," << names[m] << "_" << si_unit(units[m]);
    csv << "\n";
    // --json: one object, SI units, instead of the table.
    nlohmann::ordered_json json;
    if (o.json) {
        nlohmann::ordered_json defs = nlohmann::ordered_json::object();
        for (uint32_t m = 0; m < M; ++m) defs[names[m]] = {{"unit", si_unit(units[m])}, {"definition", definitions[m]}};
        json["measurements"] = defs;
        json["bodies"] = nlohmann::ordered_json::array();
    }
    if (n > 1 && !o.json) {
        std::printf("%5s", "body");
        for (uint32_t m = 0; m < M; ++m) std::printf(" %8.8s", names[m]);
        std::printf("\n");
    }
    std::vector<float> values(M);
    Progress progress("measure");
    for (uint32_t i = 0; i < n; ++i) {
        if (!progress.update("body " + std::to_string(i + 1) + " of " + std::to_string(n))) {
            std::fprintf(stderr, "sscape measure: cancelled (Ctrl-C); no file written\n");
            return 130;
        }
        std::vector<float> shape = o.shape;
        if (o.random) shape.assign(random.begin() + std::ptrdiff_t(i) * K, random.begin() + std::ptrdiff_t(i + 1) * K);
        // The C++ measurer: the C API measures bodies, not meshes, and returns no paths.
        std::vector<measure::Path> paths;
        std::vector<measure::Path>* wanted_paths = i == 0 && !o.png.empty() ? &paths : nullptr;
        std::vector<float> rest = mesh.xyz;
        std::vector<double> measured;
        if (o.mesh.empty()) {
            check(ssc_body_set_shape(guard.body, shape.data(), uint32_t(shape.size())), "shape");
            set_sliders(model, guard.body, o.sliders);
            shape.resize(K);
            check(ssc_body_get_shape(guard.body, shape.data(), K), "shape");  // what the sliders made of it
            measured = measurer_of(model).measure(body_of(guard.body), wanted_paths);
            if (wanted_paths) {
                rest.resize(3ull * ssc_model_vertex_count(model));
                check(ssc_body_get_rest_vertices(guard.body, rest.data(), ssc_model_vertex_count(model), 0), "rest vertices");
            }
        } else {
            measured = measurer_of(model).measure(mesh.xyz.data(), mesh.joints.data(), wanted_paths);
        }
        for (uint32_t m = 0; m < M; ++m) values[m] = float(measured[m]);
        csv << i;
        for (uint32_t m = 0; m < M; ++m) csv << "," << values[m];
        csv << "\n";
        progress.clear();  // the row goes where the progress line was
        if (o.json) {
            nlohmann::ordered_json values_by_name = nlohmann::ordered_json::object();
            for (uint32_t m = 0; m < M; ++m) values_by_name[names[m]] = values[m];
            nlohmann::ordered_json body = nlohmann::ordered_json::object();
            if (o.mesh.empty()) body["shape"] = shape;
            else body["mesh"] = o.mesh;
            body["values"] = values_by_name;
            json["bodies"].push_back(body);
        } else if (n == 1) {
            for (uint32_t m = 0; m < M; ++m) {
                const Shown s = shown(units[m]);
                std::printf("%-18s %9.2f %s\n", names[m], s.factor * values[m], s.unit);
                if (o.definitions) std::printf("    %s\n", definitions[m]);
            }
        } else {
            std::printf("%5u", i);
            for (uint32_t m = 0; m < M; ++m) std::printf(" %8.2f", shown(units[m]).factor * values[m]);
            std::printf("\n");
        }
        if (i == 0 && !o.png.empty()) {
            const uint32_t T = ssc_model_triangle_count(model);
            std::vector<uint32_t> tris(3ull * T);
            check(ssc_model_get_triangles(model, tris.data(), T), "triangles");
            render::write_measurement_picture(o.png, rest, tris, paths);
        }
    }
    if (o.json) std::printf("%s\n", json.dump(2).c_str());
    else if (n > 1) std::printf("units: cm, m2 (surface_area), L (volume), kg (mass)\n");
    if (!o.csv.empty()) {
        const std::string text = csv.str();
        write_file_atomically(o.csv, text.data(), text.size());
    }
    return 0;
}

}  // namespace

Run add_measure(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("measure", "body measurements (stature, girths, lengths, surface area, volume, mass) of one shape "
                                                "or of random shapes, as a table, CSV or JSON, and a picture of where they are taken");
    add_model_argument(*c, o->model);
    CLI::Option* shape = c->add_option("--shape", o->shape_text, "shape coefficients in standard deviations; those left out are 0 (the mean body)")
                             ->type_name("C1,C2,...");
    CLI::Option* sliders = c->add_option("--sliders", o->sliders_text, "move semantic sliders from the shape (SI units; sscape info lists them)")
                               ->type_name("NAME=V,...");
    CLI::Option* params = c->add_option("--params", o->params, "the shape of a fit, as sscape fit --params wrote it (measured at rest)")
                              ->type_name("FIT.json")->excludes(shape);
    CLI::Option* mesh = c->add_option("--mesh", o->mesh, "measure a mesh with the model's vertices (OBJ or PLY: a body sscape synth wrote, "
                                                         "or a registration, brought to rest when its report is beside it)")
                            ->type_name("BODY.obj|.ply")->excludes(shape)->excludes(sliders)->excludes(params);
    c->add_option("--units", o->units, "units of the --mesh file (default m; a registration's report gives its own)")
        ->check(CLI::IsMember({"m", "cm", "mm"}))->type_name("m|cm|mm");
    c->add_option("--random", o->random, "measure N random shapes (coefficients standard normal, truncated at 2.5 SD)")
        ->check(CLI::Range(1u, 10000u))->type_name("N")->excludes(shape)->excludes(sliders)->excludes(params)->excludes(mesh);
    c->add_option("--seed", o->seed, "random seed for --random")->capture_default_str();
    c->add_option("--csv", o->csv, "write one row per body in SI units (m, m2, m3, kg)")->type_name("OUT.csv");
    c->add_option("--png", o->png, "draw where each measurement is taken on the first body")->type_name("OUT.png")->check(extension(".png"));
    c->add_flag("--definitions", o->definitions, "print each measurement's definition (ISO 8559-1 / ISO 7250-1 where they define it)");
    c->add_flag("--json", o->json, "print one JSON object in SI units, with the definitions, instead of the table");
    return [o] { return run_measure(*o); };
}

}  // namespace ssc::cli
