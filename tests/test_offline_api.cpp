// The offline tools' C API (sscape_offline.h): a folder's scans, one scan file registered into its
// record (and reused, and registered again when its file changes), and bootstrapping's refusals and
// jobs. The whole bootstrapping through it is tested by the CLI and Python pipeline tests.
#include "support.hpp"

#include "common/files.hpp"
#include "learning/learn_model.hpp"
#include "simulation/simulate.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/model.hpp"

#include <sscape/sscape_offline.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

using namespace ssc;
namespace fs = std::filesystem;

namespace {

// An ASCII PLY of points (x y z), scaled: the scanner's file.
void write_points(const std::string& path, const std::vector<Eigen::Vector3d>& points, double scale) {
    std::ofstream f(path);
    f << "ply\nformat ascii 1.0\nelement vertex " << points.size() << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (const auto& p : points) f << p.x() * scale << " " << p.y() * scale << " " << p.z() * scale << "\n";
}

// A posed body of the model with bumps, scanned: 6,000 points, 1 mm noise, holes.
std::vector<Eigen::Vector3d> scan_points(uint32_t seed) {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(seed);
    simulation::TrueBody truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.2), Eigen::Vector3d::Zero());
    simulation::add_bumps(truth, m, 6, rng);
    simulation::CloudSpec spec;
    spec.points = 6000;
    spec.noise = 0.001;
    spec.missing = 0.1;
    spec.outliers = 0;
    return simulation::simulate_cloud(m, truth, spec, rng).points;
}

std::string last_error() { return ssc_last_error(); }

}  // namespace

TEST_CASE("a folder's scans are listed by name with their landmark files", "[capi][offline]") {
    const std::string dir = test::fresh_folder("offline_api", "list");
    for (const char* name : {"b.ply", "a.OBJ", "a.lnd", "c_scan.ply", "c.lnd", "notes.txt"}) std::ofstream(dir + "/" + name) << "x";
    fs::create_directories(dir + "/sub.ply");  // a folder, not a scan
    ssc_scan_list* list = nullptr;
    CHECK(ssc_scan_list_create(nullptr, &list) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_scan_list_create((dir + "/missing").c_str(), &list) == SSC_ERROR_IO);
    CHECK(list == nullptr);
    REQUIRE(ssc_scan_list_create(dir.c_str(), &list) == SSC_OK);
    REQUIRE(ssc_scan_list_count(list) == 3);
    const char *name = nullptr, *path = nullptr, *lnd = nullptr;
    REQUIRE(ssc_scan_list_get(list, 0, &name, &path, &lnd) == SSC_OK);
    CHECK(std::string(name) == "a");
    CHECK(std::string(lnd) == dir + "/a.lnd");
    REQUIRE(ssc_scan_list_get(list, 1, &name, &path, &lnd) == SSC_OK);
    CHECK((std::string(name) == "b" && std::string(lnd).empty()));
    REQUIRE(ssc_scan_list_get(list, 2, &name, nullptr, &lnd) == SSC_OK);
    CHECK((std::string(name) == "c_scan" && std::string(lnd) == dir + "/c.lnd"));  // the simulator's PREFIX_scan.ply
    CHECK(ssc_scan_list_get(list, 3, &name, &path, &lnd) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_scan_list_count(nullptr) == 0);
    CHECK(ssc_scan_list_skipped_count(list) == 0);
    ssc_scan_list_destroy(list);
    ssc_scan_list_destroy(nullptr);
}

TEST_CASE("a loop of links or a link to nothing in a scans folder is left out and said, not an internal error", "[capi][offline]") {
    // One stale link once stopped a whole collection with SSC_ERROR_INTERNAL ("Too many levels of
    // symbolic links"); it is left out of the list, with the reason, and bootstrapping goes on.
    const std::string dir = test::fresh_folder("offline_api", "links"), scans = dir + "/scans";
    fs::create_directories(scans);
    for (int i = 1; i <= 3; ++i) write_points(scans + "/p" + std::to_string(i) + ".ply", scan_points(uint32_t(i)), 1.0);
    fs::create_symlink("loop_b.ply", scans + "/loop_a.ply");
    fs::create_symlink("loop_a.ply", scans + "/loop_b.ply");
    fs::create_symlink("nowhere.ply", scans + "/stale.ply");
    ssc_scan_list* list = nullptr;
    REQUIRE(ssc_scan_list_create(scans.c_str(), &list) == SSC_OK);
    CHECK(ssc_scan_list_count(list) == 3);
    REQUIRE(ssc_scan_list_skipped_count(list) == 3);
    const char *path = nullptr, *reason = nullptr;
    REQUIRE(ssc_scan_list_get_skipped(list, 0, &path, &reason) == SSC_OK);
    CHECK(std::string(path) == scans + "/loop_a.ply");
    CHECK(std::string(reason).find("symbolic links") != std::string::npos);
    REQUIRE(ssc_scan_list_get_skipped(list, 2, &path, nullptr) == SSC_OK);
    CHECK(std::string(path) == scans + "/stale.ply");
    REQUIRE(ssc_scan_list_get_skipped(list, 2, nullptr, &reason) == SSC_OK);
    CHECK(std::string(reason) == "a link to nothing");
    CHECK(ssc_scan_list_get_skipped(list, 3, &path, &reason) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_scan_list_get_skipped(nullptr, 0, &path, &reason) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_scan_list_skipped_count(nullptr) == 0);
    ssc_scan_list_destroy(list);
    // Bootstrapping lists the folder the same way: its three scans.
    ssc_bootstrap_def def;
    ssc_bootstrap_def_init(&def, sizeof def);
    const std::string out = dir + "/out";
    def.scans_dir = scans.c_str();
    def.out_dir = out.c_str();
    def.components = 2;
    ssc_bootstrap* b = nullptr;
    REQUIRE(ssc_bootstrap_create(nullptr, &def, &b) == SSC_OK);
    CHECK(ssc_bootstrap_scan_count(b) == 3);
    ssc_bootstrap_destroy(b);
}

TEST_CASE("a scan file is registered into its record, reused while current, and refused when it is no body", "[capi][offline]") {
    const std::string dir = test::fresh_folder("offline_api", "run_file");
    write_points(dir + "/scan.ply", scan_points(5), 1000.0);  // millimetres
    ssc_model* model = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &model) == SSC_OK);
    ssc_registration* reg = nullptr;
    REQUIRE(ssc_registration_create(model, nullptr, &reg) == SSC_OK);
    ssc_scan_file_job job;
    ssc_scan_file_job_init(&job, sizeof job);
    CHECK(job.write_report == 1);
    CHECK(job.reuse == 0);
    const std::string scan = dir + "/scan.ply", mesh = dir + "/out.ply";
    ssc_registration_report report;
    report.struct_size = sizeof report;
    uint32_t reused = 7;
    CHECK(ssc_registration_run_file(reg, nullptr, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);  // no paths
    CHECK(last_error().find("scan_path is NULL") != std::string::npos);
    job.scan_path = scan.c_str();
    job.mesh_path = mesh.c_str();
    // Millimetres read as metres: refused, with the units that fit.
    CHECK(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(last_error().find("in mm it would span") != std::string::npos);
    job.units = "km";
    CHECK(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(last_error().find("none of m, cm, mm") != std::string::npos);
    job.units = "mm";
    job.up = "w";
    CHECK(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    job.up = nullptr;
    job.write_report = 0;
    job.reuse = 1;
    CHECK(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(!fs::exists(mesh));
    CHECK(reused == 7);  // nothing written on failure

    job.write_report = 1;
    REQUIRE(ssc_registration_run_file(reg, &job, nullptr, nullptr, &report, &reused) == SSC_OK);
    CHECK(reused == 0);
    CHECK(report.scan_points == 6000);
    CHECK(report.rounds == 6);
    CHECK(report.quality.scan_mean < 0.003f);
    CHECK(ssc_registration_region_count(reg) == 6);
    const std::string bytes = read_regular_file(mesh, 1u << 30), json = read_regular_file(dir + "/out.json", 1u << 30);
    CHECK(json.find("\"model_digest\"") != std::string::npos);
    CHECK(json.find("\"scan_units_to_metres\": 0.001") != std::string::npos);
    CHECK(json.find("\"fit_segments\": true") != std::string::npos);  // the default
    const float seconds = report.seconds;

    // Again: reused from the files (the same report), nothing written.
    ssc_registration_report again;
    again.struct_size = sizeof again;
    REQUIRE(ssc_registration_run_file(reg, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
    CHECK(reused == 1);
    CHECK(again.seconds == Approx(seconds));
    CHECK(again.valid_vertices == report.valid_vertices);
    CHECK(ssc_registration_region_count(reg) == 0);  // no result held
    CHECK(read_regular_file(mesh, 1u << 30) == bytes);

    // The same model file's bytes loaded another way: the same digest, reused.
    const std::string model_bytes = read_regular_file(test::default_model_file(), 1u << 30);
    ssc_model* same = nullptr;
    REQUIRE(ssc_model_load_memory(nullptr, model_bytes.data(), model_bytes.size(), &same) == SSC_OK);
    ssc_registration* reg_same = nullptr;
    REQUIRE(ssc_registration_create(same, nullptr, &reg_same) == SSC_OK);
    REQUIRE(ssc_registration_run_file(reg_same, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
    CHECK(reused == 1);
    // Another model (its template alone), the model fit without segments, back to the first model,
    // and a changed scan: registered again (not under the sanitizers: the same code five times
    // more, minutes there).
    if (!test::sanitized) {
        const std::vector<unsigned char> other_bytes =
            format::write_model(learning::template_only(format::read_model(model_bytes.data(), model_bytes.size())));
        ssc_model* other = nullptr;
        REQUIRE(ssc_model_load_memory(nullptr, other_bytes.data(), other_bytes.size(), &other) == SSC_OK);
        ssc_registration* reg_other = nullptr;
        REQUIRE(ssc_registration_create(other, nullptr, &reg_other) == SSC_OK);
        REQUIRE(ssc_registration_run_file(reg_other, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
        CHECK(reused == 0);
        CHECK(read_regular_file(mesh, 1u << 30) != bytes);
        ssc_registration_destroy(reg_other);
        ssc_model_release(other);
        // The model fit without the segment shape spaces is another setting: registered again, then reused.
        ssc_registration_def whole_body;
        ssc_registration_def_init(&whole_body, sizeof whole_body);
        whole_body.fit_segments = 0;
        ssc_registration* reg_whole = nullptr;
        REQUIRE(ssc_registration_create(model, &whole_body, &reg_whole) == SSC_OK);
        REQUIRE(ssc_registration_run_file(reg_whole, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
        CHECK(reused == 0);
        CHECK(read_regular_file(dir + "/out.json", 1u << 30).find("\"fit_segments\": false") != std::string::npos);
        REQUIRE(ssc_registration_run_file(reg_whole, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
        CHECK(reused == 1);
        ssc_registration_destroy(reg_whole);
        REQUIRE(ssc_registration_run_file(reg, &job, nullptr, nullptr, &again, &reused) == SSC_OK);
        CHECK(reused == 0);
        CHECK(read_regular_file(mesh, 1u << 30) == bytes);  // the same registration, to the byte
        write_points(scan, scan_points(6), 1000.0);
        const ssc_status changed = ssc_registration_run_file(reg, &job, nullptr, nullptr, &again, &reused);
        INFO(last_error());
        REQUIRE(changed == SSC_OK);
        CHECK(reused == 0);
        CHECK(read_regular_file(mesh, 1u << 30) != bytes);
    }
    // A cancel writes nothing.
    fs::remove(mesh);
    fs::remove(dir + "/out.json");
    const ssc_stage_progress_fn stop = [](void*, const char* stage, uint32_t, uint32_t) { return std::string(stage) == "deform" ? 1 : 0; };
    CHECK(ssc_registration_run_file(reg, &job, stop, nullptr, &again, &reused) == SSC_ERROR_CANCELLED);
    CHECK(!fs::exists(mesh));
    CHECK(!fs::exists(dir + "/out.json"));
    // A scan that cannot be registered: with reuse, its failure is kept and repeated at once, until
    // the scan changes.
    const std::string broken = dir + "/broken.ply", broken_mesh = dir + "/broken_out.ply";
    std::ofstream(broken) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
    ssc_scan_file_job bad = job;
    bad.scan_path = broken.c_str();
    bad.mesh_path = broken_mesh.c_str();
    bad.reuse = 1;
    CHECK(ssc_registration_run_file(reg, &bad, nullptr, nullptr, &again, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    const std::string reason = last_error();
    CHECK(fs::exists(dir + "/broken_out.failed.json"));
    CHECK(!fs::exists(broken_mesh));
    CHECK(ssc_registration_run_file(reg, &bad, nullptr, nullptr, &again, &reused) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(last_error() == reason);
    fs::copy_file(scan, broken, fs::copy_options::overwrite_existing);  // mended
    REQUIRE(ssc_registration_run_file(reg, &bad, nullptr, nullptr, &again, &reused) == SSC_OK);
    CHECK(reused == 0);
    CHECK(!fs::exists(dir + "/broken_out.failed.json"));
    CHECK(fs::exists(broken_mesh));

    ssc_registration_destroy(reg_same);
    ssc_model_release(same);
    ssc_registration_destroy(reg);
    ssc_model_release(model);
}

TEST_CASE("a fitter reads scan and landmark files as sscape fit does and writes its parameters", "[capi][offline]") {
    const std::string dir = test::fresh_folder("offline_api", "fit_files");
    write_points(dir + "/scan.ply", scan_points(7), 100.0);  // centimetres
    std::ofstream(dir + "/few.lnd") << "AUX =\n1 0 1 0.00 10 20 30 Sellion\nEND =\n";  // one landmark
    ssc_model* model = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &model) == SSC_OK);
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(model, nullptr, &fitter) == SSC_OK);
    ssc_fit_file_def def;
    ssc_fit_file_def_init(&def, sizeof def);
    ssc_fit_file_info info;
    info.struct_size = sizeof info;
    CHECK(ssc_fitter_add_points_file(fitter, 0, &def, &info) == SSC_ERROR_INVALID_ARGUMENT);  // no path
    CHECK(ssc_fitter_add_points_file(nullptr, 0, &def, &info) == SSC_ERROR_INVALID_ARGUMENT);
    const std::string scan = dir + "/scan.ply", few = dir + "/few.lnd", missing = dir + "/none.ply";
    def.path = missing.c_str();
    CHECK(ssc_fitter_add_points_file(fitter, 0, &def, &info) == SSC_ERROR_IO);
    def.path = scan.c_str();
    def.units_option = "--units";
    CHECK(ssc_fitter_add_points_file(fitter, 0, &def, &info) == SSC_ERROR_INVALID_ARGUMENT);  // centimetres read as metres
    CHECK(last_error().find("with --units cm it would span") != std::string::npos);
    def.units = "cm";
    REQUIRE(ssc_fitter_add_points_file(fitter, 0, &def, &info) == SSC_OK);
    CHECK(info.used == 6000);
    CHECK(info.left_out == 6000);  // an ASCII PLY without normals: every normal estimated
    CHECK((info.span > 1.0f && info.span < 2.5f));
    def.path = few.c_str();
    def.units = nullptr;
    CHECK(ssc_fitter_add_landmarks_file(fitter, 0, &def, &info) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(last_error().find("fewer than 3 usable landmarks") != std::string::npos);
    ssc_fit_report report;
    report.struct_size = sizeof report;
    const std::string params = dir + "/params.json";
    CHECK(ssc_fitter_write_params(fitter, &report, params.c_str()) == SSC_ERROR_INVALID_ARGUMENT);  // not solved
    CHECK(!fs::exists(params));
    REQUIRE(ssc_fitter_solve(fitter, nullptr, nullptr, &report) == SSC_OK);
    // Read right (centimetres as such): the fit explains the scan (a body with bumps it cannot take on).
    CHECK(report.unexplained_fraction < SSC_FIT_UNEXPLAINED_LIMIT);
    CHECK(report.point_mean < 0.015f);
    REQUIRE(ssc_fitter_write_params(fitter, &report, params.c_str()) == SSC_OK);
    const std::string json = read_regular_file(params, 1u << 20);
    CHECK(json.find("\"format\": \"sscape fit parameters 2\"") != std::string::npos);
    CHECK(json.find("\"upperarm_l\"") != std::string::npos);
    // The model's digest, what a reader checks its model against: the built-in file's bytes'.
    const char* digest = nullptr;
    CHECK(ssc_model_get_digest(nullptr, &digest) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_digest(model, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_model_get_digest(model, &digest) == SSC_OK);
    const std::string file = read_regular_file(test::default_model_file(), 1u << 30);
    CHECK(std::string(digest) == content_digest(file.data(), file.size()));
    CHECK(json.find("\"model_digest\": \"" + std::string(digest) + "\"") != std::string::npos);
    ssc_fitter_destroy(fitter);
    ssc_model_release(model);
}

TEST_CASE("bootstrapping refuses bad settings before writing, and gives each round's registration jobs", "[capi][offline]") {
    const std::string dir = test::fresh_folder("offline_api", "bootstrap"), scans = dir + "/scans", out = dir + "/out";
    fs::create_directories(scans);
    write_points(scans + "/p1.ply", scan_points(1), 1.0);
    write_points(scans + "/p2.ply", scan_points(2), 1.0);
    ssc_bootstrap_def def;
    ssc_bootstrap_def_init(&def, sizeof def);
    CHECK(def.components == 20);
    CHECK(def.contact_sheet_entries == 12);
    CHECK(def.fit_segments == 1);
    ssc_bootstrap* b = nullptr;
    CHECK(ssc_bootstrap_create(nullptr, nullptr, &b) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_INVALID_ARGUMENT);  // no folders
    def.scans_dir = scans.c_str();
    def.out_dir = out.c_str();
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(last_error().find("holds 2 scans") != std::string::npos);
    write_points(scans + "/p3.ply", scan_points(3), 1.0);
    def.components = 0;
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_INVALID_ARGUMENT);
    def.components = 2;
    def.posture = static_cast<ssc_posture_normalization>(9);
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_INVALID_ARGUMENT);
    def.posture = SSC_POSTURE_LAPLACIAN;  // accepted; creating writes nothing
    REQUIRE(ssc_bootstrap_create(nullptr, &def, &b) == SSC_OK);
    ssc_bootstrap_destroy(b);
    b = nullptr;
    def.posture = SSC_POSTURE_SKELETON;
    def.units = "inch";
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_INVALID_ARGUMENT);
    def.units = nullptr;
    const std::string missing = dir + "/none.sscape";
    def.init_model_path = missing.c_str();
    CHECK(ssc_bootstrap_create(nullptr, &def, &b) == SSC_ERROR_IO);
    def.init_model_path = nullptr;
    CHECK(b == nullptr);
    CHECK(!fs::exists(out));

    REQUIRE(ssc_bootstrap_create(nullptr, &def, &b) == SSC_OK);
    CHECK(!fs::exists(out));  // nothing written yet
    REQUIRE(ssc_bootstrap_scan_count(b) == 3);
    const char* name = nullptr;
    REQUIRE(ssc_bootstrap_get_scan(b, 2, &name, nullptr, nullptr) == SSC_OK);
    CHECK(std::string(name) == "p3");
    REQUIRE(ssc_bootstrap_prepare(b) == SSC_OK);
    CHECK(fs::exists(out + "/round_0/model.sscape"));
    ssc_scan_file_job job;
    ssc_scan_file_job_init(&job, sizeof job);
    const char* model_path = nullptr;
    CHECK(ssc_bootstrap_get_job(b, 0, 0, &job, &model_path) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_bootstrap_get_job(b, 1, 3, &job, &model_path) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_bootstrap_get_job(b, 2, 1, &job, &model_path) == SSC_OK);
    CHECK(std::string(job.mesh_path) == out + "/round_2/registrations/p2.ply");
    CHECK(std::string(model_path) == out + "/round_1/model.sscape");
    CHECK(std::string(job.scan_path) == scans + "/p2.ply");
    CHECK(job.reuse == 1);
    CHECK(fs::is_directory(out + "/round_2/registrations"));
    CHECK(ssc_bootstrap_run(b, 0, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    // A second bootstrapping into the folder in use is refused (two once both said "wrote
    // model.sscape" and the folder kept the second's); once the first ends, it may start.
    ssc_bootstrap* second = nullptr;
    REQUIRE(ssc_bootstrap_create(nullptr, &def, &second) == SSC_OK);  // reading the inputs writes nothing
    const std::string model_before = read_regular_file(out + "/round_0/model.sscape", 1u << 30);
    CHECK(ssc_bootstrap_prepare(second) == SSC_ERROR_IO);
    CHECK(last_error().find("the output folder " + out + " is in use by another bootstrap (process ") != std::string::npos);
    CHECK(ssc_bootstrap_run(second, 1, nullptr, nullptr) == SSC_ERROR_IO);
    CHECK(read_regular_file(out + "/round_0/model.sscape", 1u << 30) == model_before);
    ssc_bootstrap_destroy(b);
    CHECK(ssc_bootstrap_prepare(second) == SSC_OK);
    ssc_bootstrap_destroy(second);
    ssc_bootstrap_destroy(nullptr);
}
