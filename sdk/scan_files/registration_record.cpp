#include "scan_files/registration_record.hpp"

#include "common/error.hpp"
#include "common/axes.hpp"
#include "common/files.hpp"
#include "common/rigid.hpp"
#include "export/mesh_writers.hpp"
#include "io/readers.hpp"
#include "fitting/body_orientation.hpp"
#include "scan_files/fit_params.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace ssc::scan_files {

namespace {

using nlohmann::ordered_json;

const std::vector<std::string> kAxes = {"x", "y", "z", "-x", "-y", "-z"};
constexpr uint64_t kMaxReport = 64ull << 20;
constexpr double kUnits[] = {1.0, 0.01, 0.001};

ordered_json quality_json(const registration::DistanceSummary& d, const std::array<double, 4>& below) {
    return ordered_json{{"scan_to_registration_mean_m", d.mean},
                        {"scan_to_registration_median_m", d.median},
                        {"scan_to_registration_p95_m", d.p95},
                        {"scan_points", d.count},
                        {"scan_points_beyond_20_mm", d.beyond_20mm},
                        {"vertices_within_2_5_10_20_mm", {below[0], below[1], below[2], below[3]}}};
}

// A number read from a report, within what a registration can produce (a hand-edited or corrupt
// report once reached learning with scan_units_to_metres 1e-300 and wrote a broken model).
double in_range(const ordered_json& j, const char* key, double lo, double hi) {
    const double x = j.at(key).get<double>();
    SSC_REQUIRE_ARG_S(std::isfinite(x) && x >= lo && x <= hi, "the report's " << key << " " << x << " is outside [" << lo << ", " << hi << "]");
    return x;
}

// A count read from a report: a whole number in [0, hi], `fallback` when absent. (nlohmann casts a
// float like 3.7e52 to an integer type unchecked, undefined behaviour the fuzz target found.)
uint64_t whole_in(const ordered_json& j, const char* key, uint64_t hi, uint64_t fallback) {
    if (!j.contains(key)) return fallback;
    const ordered_json& v = j.at(key);
    SSC_REQUIRE_ARG_S(v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0),
                      "the report's " << key << " is not a whole number >= 0");
    const uint64_t x = v.is_number_unsigned() ? v.get<uint64_t>() : uint64_t(v.get<int64_t>());
    SSC_REQUIRE_ARG_S(x <= hi, "the report's " << key << " " << x << " is above " << hi);
    return x;
}

void quality_from_json(const ordered_json& j, registration::DistanceSummary& d, std::array<double, 4>& below) {
    d.mean = in_range(j, "scan_to_registration_mean_m", 0, 1e3);
    d.median = in_range(j, "scan_to_registration_median_m", 0, 1e3);
    d.p95 = in_range(j, "scan_to_registration_p95_m", 0, 1e3);
    d.count = whole_in(j, "scan_points", 1ull << 40, 0);  // sscape register's reports have no counts
    d.beyond_20mm = whole_in(j, "scan_points_beyond_20_mm", d.count ? d.count : 1ull << 40, 0);
    const std::vector<double> b = j.at("vertices_within_2_5_10_20_mm");
    SSC_REQUIRE_ARG(b.size() == 4, "vertices_within_2_5_10_20_mm needs 4 shares");
    for (double x : b) SSC_REQUIRE_ARG_S(std::isfinite(x) && x >= 0 && x <= 1, "the report's vertices_within_2_5_10_20_mm holds " << x << ", not a share");
    std::copy(b.begin(), b.end(), below.begin());
}

}  // namespace

std::string record_report_path(const std::string& mesh_path) { return std::filesystem::path(mesh_path).replace_extension(".json").string(); }


std::string model_digest(const std::vector<unsigned char>& model_file) { return content_digest(model_file.data(), model_file.size()); }
std::string file_digest(const std::string& bytes) { return content_digest(bytes.data(), bytes.size()); }

RecordBytes write_registration_record(const std::string& mesh_path, const Model& model, const RegistrationRecord& r, bool with_report) {
    const uint32_t V = model.vertex_count();
    SSC_REQUIRE_ARG(r.registered.vertices.size() == V, "registration record: vertex count differs from the model's");
    SSC_REQUIRE_ARG(std::find(kAxes.begin(), kAxes.end(), r.scan_up) != kAxes.end(), "registration record: scan_up is no axis");
    // The mesh in the scan's frame and units, as `sscape register` writes it.
    const Eigen::Matrix3d R = up_axis_rotation(r.scan_up);
    std::vector<float> xyz(3ull * V);
    for (uint32_t v = 0; v < V; ++v) {
        const Eigen::Vector3d back = R.transpose() * r.registered.vertices[v] / r.scan_units_to_metres;
        for (int a = 0; a < 3; ++a) xyz[3ull * v + std::size_t(a)] = float(back[a]);
    }
    exporters::MeshView mesh;
    mesh.vertex_count = V;
    mesh.positions = xyz.data();
    mesh.triangle_count = uint32_t(model.data().mesh.triangles.size() / 3);
    mesh.triangles = model.data().mesh.triangles.data();
    RecordBytes written;
    written.mesh = exporters::mesh_bytes(mesh_path, mesh);
    write_file_atomically(mesh_path, written.mesh.data(), written.mesh.size());
    if (!with_report) return written;

    ordered_json j;
    j["scan"] = r.scan;
    j["scan_units_to_metres"] = r.scan_units_to_metres;
    j["scan_up"] = r.scan_up;
    // The scan's own axis nearest the fitted body's up: where it differs from scan_up, the scan was
    // written with another up (the fit, which tries every orientation, found the body anyway).
    if (r.registered.has_fit)
        j["scan_up_found"] = nearest_axis_name(up_axis_rotation(r.scan_up).transpose() *
                                               fitting::fitted_body_orientation(model.data(), r.registered.fit).col(1));
    j["fit_segments"] = r.fit_segments;
    j["seconds"] = r.seconds;
    j["fit_seconds"] = r.fit_seconds;
    j["rounds"] = r.rounds;
    j["solves"] = r.solves;
    if (!r.valid.empty()) j["valid_vertices"] = std::count(r.valid.begin(), r.valid.end(), uint8_t(1));
    if (!r.model_digest.empty()) j["model_digest"] = r.model_digest;
    if (!r.scan_digest.empty()) j["scan_digest"] = r.scan_digest;
    j["quality"] = quality_json(r.quality.scan_to_registration, r.quality.below);
    ordered_json regions = ordered_json::object();
    for (const auto& q : r.quality.regions) regions[q.region] = quality_json(q.scan_to_registration, q.below);
    j["regions"] = regions;
    if (r.registered.has_fit) j["fit"] = fit_to_json(model, r.registered.fit, r.model_digest);
    if (!r.quality.vertex_distance.empty()) {
        std::vector<double> mm;  // rounded to 0.01 mm: the report stays small
        for (double d : r.quality.vertex_distance) mm.push_back(d < 0 ? -1.0 : std::round(d * 1e5) / 100);
        j["vertex_distance_mm"] = mm;
    }
    if (!r.valid.empty()) j["valid"] = r.valid;
    // A scan's file name need not be UTF-8, which JSON must be: such bytes are written as U+FFFD
    // (the path is for people; reuse goes by the files' digests).
    written.report = j.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    write_file_atomically(record_report_path(mesh_path), written.report.data(), written.report.size());
    return written;
}

RegistrationRecord read_registration_record(const std::string& mesh_path, const Model& model, bool need_fit) {
    const std::string path = record_report_path(mesh_path);
    if (!std::filesystem::exists(path))
        throw Error(SSC_ERROR_IO, mesh_path + ": no registration report " + path + " (sscape register --report writes it)");
    RecordBytes bytes;
    bytes.report = read_regular_file(path, kMaxReport);
    bytes.mesh = read_regular_file(mesh_path, io::kMaxInputBytes);
    return registration_record_from_bytes(mesh_path, bytes, model, need_fit);
}

RegistrationRecord registration_record_from_bytes(const std::string& mesh_path, const RecordBytes& bytes, const Model& model, bool need_fit) {
    const std::string path = record_report_path(mesh_path);
    RegistrationRecord r = parse_registration_report(bytes.report, path, model, need_fit);
    r.registered.name = mesh_path;
    const Eigen::Matrix3d R = up_axis_rotation(r.scan_up);
    for (const auto& p : io::parse_points(bytes.mesh, mesh_path).points) r.registered.vertices.push_back(R * (p * r.scan_units_to_metres));
    if (r.registered.vertices.size() != model.vertex_count())
        throw Error(SSC_ERROR_INVALID_ARGUMENT, mesh_path + ": " + std::to_string(r.registered.vertices.size()) + " vertices; the model has " +
                                                    std::to_string(model.vertex_count()) + " (was it registered with this model?)");
    return r;
}

RegistrationRecord parse_registration_report(const std::string& text, const std::string& path, const Model& model, bool need_fit) {
    ordered_json j;  // keeps the regions in the order they were written
    try {
        j = ordered_json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw Error(SSC_ERROR_INVALID_ARGUMENT, path + ": not a registration report: " + e.what());
    }
    RegistrationRecord r;
    const uint32_t V = model.vertex_count();
    try {
        SSC_REQUIRE_ARG(j.is_object(), "not a JSON object");
        r.scan = j.value("scan", "");
        r.scan_up = j.value("scan_up", "y");
        r.scan_units_to_metres = j.value("scan_units_to_metres", 1.0);
        r.fit_segments = j.value("fit_segments", false);
        r.seconds = j.contains("seconds") ? in_range(j, "seconds", 0, 1e9) : 0.0;
        r.fit_seconds = j.contains("fit_seconds") ? in_range(j, "fit_seconds", 0, 1e9) : 0.0;
        r.rounds = uint32_t(whole_in(j, "rounds", 1000000, 0));
        r.solves = uint32_t(whole_in(j, "solves", 1000000000, 0));
        r.model_digest = j.value("model_digest", "");
        r.scan_digest = j.value("scan_digest", "");
        // The units a scan can be read in (io::units_to_metres): m, cm, mm.
        const bool unit = std::any_of(std::begin(kUnits), std::end(kUnits), [&](double u) { return std::abs(r.scan_units_to_metres - u) <= 1e-9 * u; });
        SSC_REQUIRE_ARG_S(unit, "the report's scan_units_to_metres " << r.scan_units_to_metres << " is none of m, cm, mm (1, 0.01, 0.001)");
        SSC_REQUIRE_ARG_S(std::find(kAxes.begin(), kAxes.end(), r.scan_up) != kAxes.end(), "the report's scan_up '" << r.scan_up << "' is no axis");
        if (j.contains("quality")) quality_from_json(j.at("quality"), r.quality.scan_to_registration, r.quality.below);
        if (j.contains("regions"))
            for (const auto& [name, q] : j.at("regions").items()) {
                registration::RegionQuality rq;
                rq.region = name;
                quality_from_json(q, rq.scan_to_registration, rq.below);
                r.quality.regions.push_back(rq);
            }
        if (j.contains("vertex_distance_mm")) {
            const std::vector<double> mm = j.at("vertex_distance_mm");
            SSC_REQUIRE_ARG(mm.size() == V, "vertex_distance_mm has a value per vertex of another model");
            for (double d : mm) {
                SSC_REQUIRE_ARG_S(std::isfinite(d) && d <= 1e6, "the report's vertex_distance_mm holds " << d);
                r.quality.vertex_distance.push_back(d < 0 ? -1.0 : d * 1e-3);
            }
        }
        if (j.contains("valid")) {
            const ordered_json& flags = j.at("valid");
            SSC_REQUIRE_ARG(flags.is_array(), "valid is not an array of flags");
            for (const ordered_json& f : flags) {
                SSC_REQUIRE_ARG(f.is_number_integer() && (f.get<int64_t>() == 0 || f.get<int64_t>() == 1), "valid holds a value other than 0 and 1");
                r.valid.push_back(uint8_t(f.get<int64_t>()));
            }
            SSC_REQUIRE_ARG(r.valid.size() == V, "valid has a flag per vertex of another model");
        }
        if (j.contains("fit")) {
            r.registered.fit = fit_from_json(j.at("fit"), model);
            r.registered.has_fit = true;
        }
    } catch (const nlohmann::json::exception& e) {
        throw Error(SSC_ERROR_INVALID_ARGUMENT, path + ": the report is malformed: " + e.what());
    } catch (const Error& e) {
        throw Error(e.status(), path + ": " + e.what());
    }
    if (!r.registered.has_fit && need_fit)
        throw Error(SSC_ERROR_INVALID_ARGUMENT, path + ": the report has no model fit (registered with --start rigid or rbf); use --posture none or laplacian");
    return r;
}

}  // namespace ssc::scan_files
