// sscape measure: the body measurements of one shape or of random shapes, as a table, CSV (SI
// units) and a picture of where they are taken.
#include "cli.hpp"

#include "capi/handles.hpp"
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
    std::vector<float> shape;
    uint32_t random = 0, seed = 1;
    bool definitions = false, json = false;
};

Options parse(const std::vector<std::string>& args) {
    Options o;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& { return option_value(args, i); };
        if (a == "--shape") o.shape = parse_floats(value(), a);
        else if (a == "--random") o.random = parse_count(value(), a);
        else if (a == "--seed") o.seed = parse_count(value(), a);
        else if (a == "--csv") o.csv = value();
        else if (a == "--png") o.png = value();
        else if (a == "--definitions") o.definitions = true;
        else if (a == "--json") o.json = true;
        else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "'");
        else if (o.model.empty()) o.model = a;
        else throw UsageError("unexpected argument '" + a + "'");
    }
    if (o.random && !o.shape.empty()) throw UsageError("--random and --shape exclude each other");
    if (o.random > 10000) throw UsageError("--random is limited to 10000 bodies");
    if (!o.png.empty() && (o.png.size() < 4 || o.png.substr(o.png.size() - 4) != ".png"))
        throw UsageError("--png needs a file name ending in .png");
    return o;
}

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

}  // namespace

int cmd_measure(const std::vector<std::string>& args) {
    const Options o = parse(args);
    ssc_model* model = load_model(o.model);
    Handles guard(model);
    const uint32_t K = ssc_model_shape_count(model), M = ssc_measurement_count();
    if (o.shape.size() > K) throw UsageError("--shape has " + std::to_string(o.shape.size()) + " values; the model has " + std::to_string(K) + " components");
    std::vector<const char*> names(M), definitions(M);
    std::vector<ssc_unit> units(M);
    for (uint32_t m = 0; m < M; ++m) check(ssc_measurement_get_info(m, &names[m], &units[m], &definitions[m]), "measurement info");
    check(ssc_body_create(model, nullptr, &guard.body), "body");

    std::mt19937 rng(o.seed);
    std::normal_distribution<float> normal;
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
    for (uint32_t i = 0; i < n; ++i) {
        std::vector<float> shape = o.shape;
        if (o.random) {
            shape.resize(K);  // standard normal, truncated at 2.5 SD as sscape synth --random
            for (float& c : shape) do c = normal(rng); while (std::abs(c) > 2.5f);
        }
        check(ssc_body_set_shape(guard.body, shape.data(), uint32_t(shape.size())), "shape");
        check(ssc_body_measure(guard.body, values.data(), M), "measure");
        csv << i;
        for (uint32_t m = 0; m < M; ++m) csv << "," << values[m];
        csv << "\n";
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
            model->measurer().measure(guard.body->body, &paths);
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

}  // namespace ssc::cli
