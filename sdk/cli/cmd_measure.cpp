// sscape measure: the body measurements of one shape or of random shapes, as a table, CSV (SI
// units) and a picture of where they are taken.
#include "cli.hpp"
#include "progress.hpp"

#include "capi/cpp_access.hpp"
#include "common/files.hpp"
#include "measure/measurements.hpp"
#include "render/measure_picture.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace ssc::cli {
namespace {

struct Options {
    std::string model, csv, png;
    std::string shape_text;
    std::vector<float> shape;
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

int run_measure(Options o) {
    if (!o.shape_text.empty()) o.shape = parse_floats(o.shape_text, "--shape");
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    const uint32_t K = ssc_model_shape_count(model), M = ssc_measurement_count();
    if (o.shape.size() > K) throw UsageError("--shape has " + std::to_string(o.shape.size()) + " values; the model has " + std::to_string(K) + " components");
    std::vector<const char*> names(M), definitions(M);
    std::vector<ssc_unit> units(M);
    for (uint32_t m = 0; m < M; ++m) check(ssc_measurement_get_info(m, &names[m], &units[m], &definitions[m]), "measurement info");
    check(ssc_body_create(model, nullptr, &guard.body), "body");

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
        check(ssc_body_set_shape(guard.body, shape.data(), uint32_t(shape.size())), "shape");
        check(ssc_body_measure(guard.body, values.data(), M), "measure");
        csv << i;
        for (uint32_t m = 0; m < M; ++m) csv << "," << values[m];
        csv << "\n";
        progress.clear();  // the row goes where the progress line was
        if (o.json) {
            nlohmann::ordered_json values_by_name = nlohmann::ordered_json::object();
            for (uint32_t m = 0; m < M; ++m) values_by_name[names[m]] = values[m];
            json["bodies"].push_back({{"shape", shape}, {"values", values_by_name}});
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
            // The first body's measurement paths (the C++ measurer: the C API returns values only).
            const uint32_t V = ssc_model_vertex_count(model), T = ssc_model_triangle_count(model);
            std::vector<float> rest(3ull * V);
            std::vector<uint32_t> tris(3ull * T);
            check(ssc_body_get_rest_vertices(guard.body, rest.data(), V, 0), "rest vertices");
            check(ssc_model_get_triangles(model, tris.data(), T), "triangles");
            std::vector<measure::Path> paths;
            measurer_of(model).measure(body_of(guard.body), &paths);
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
    c->add_option("--random", o->random, "measure N random shapes (coefficients standard normal, truncated at 2.5 SD)")
        ->check(CLI::Range(1u, 10000u))->type_name("N")->excludes(shape);
    c->add_option("--seed", o->seed, "random seed for --random")->capture_default_str();
    c->add_option("--csv", o->csv, "write one row per body in SI units (m, m2, m3, kg)")->type_name("OUT.csv");
    c->add_option("--png", o->png, "draw where each measurement is taken on the first body")->type_name("OUT.png")->check(extension(".png"));
    c->add_flag("--definitions", o->definitions, "print each measurement's definition (ISO 8559-1 / ISO 7250-1 where they define it)");
    c->add_flag("--json", o->json, "print one JSON object in SI units, with the definitions, instead of the table");
    return [o] { return run_measure(*o); };
}

}  // namespace ssc::cli
