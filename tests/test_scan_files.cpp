// The scan-file stage (sdk/scan_files): a scan read once (its digest names the bytes it is parsed
// from) and results kept on disk with their key (CachedResult).
#include "support.hpp"

#include "common/files.hpp"
#include "scan_files/cached_result.hpp"
#include "scan_files/fit_params.hpp"
#include "scan_files/scan_input.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <cmath>
#include <fstream>

using namespace ssc;
namespace fs = std::filesystem;

namespace {

// An ASCII PLY of n points on a 1.7 m tall column, shifted by dx: a body's extent.
void write_column(const std::string& path, int n, double dx) {
    std::ofstream f(path);
    f << "ply\nformat ascii 1.0\nelement vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (int i = 0; i < n; ++i) f << dx + 0.1 * (i % 3) << " " << 1.7 * i / (n - 1) << " " << 0.05 * (i % 5) << "\n";
}

}  // namespace

TEST_CASE("a scan is parsed from the bytes its digest was taken of", "[scan_files]") {
    const std::string dir = test::fresh_folder("scan_files", "read_once");
    scan_files::ScanInput in;
    in.name = "s";
    in.path = dir + "/s.ply";
    write_column(in.path, 200, 0.0);
    const scan_files::ScanBytes bytes = scan_files::read_scan_bytes(in);
    const std::string digest = scan_files::scan_digest(bytes);
    CHECK(digest == content_digest(bytes.scan.data(), bytes.scan.size()));
    // The file changes after it was read: the scan parsed is still the one the digest names.
    write_column(in.path, 200, 0.5);
    const Model& model = test::default_cpp_model();
    const registration::Scan scan = scan_files::parse_scan(bytes, in, model, scan_files::ScanReading());
    REQUIRE(scan.cloud.points.size() == 200);
    CHECK(scan.cloud.points[0].x() == 0.0);
    CHECK(scan_files::scan_digest(scan_files::read_scan_bytes(in)) != digest);
    CHECK(scan_files::load_scan(in, model, scan_files::ScanReading()).cloud.points[0].x() == 0.5);
    // A landmark file's bytes join the digest.
    in.landmarks = dir + "/s.lnd";
    std::ofstream(in.landmarks) << "AUX =\nEND =\n";
    CHECK(scan_files::scan_digest(scan_files::read_scan_bytes(in)) != scan_files::scan_digest(scan_files::ScanBytes{bytes.scan, ""}));
    // An unreadable file is an IO error before anything is parsed.
    in.path = dir + "/missing.ply";
    try {
        scan_files::read_scan_bytes(in);
        FAIL("a missing scan was read");
    } catch (const Error& e) {
        CHECK(e.status() == SSC_ERROR_IO);
    }
}

TEST_CASE("a cached result is found while its key is the same and made again when it changes", "[scan_files]") {
    const std::string dir = test::fresh_folder("scan_files", "cached");
    const std::string path = dir + "/result.json";
    const nlohmann::ordered_json key{{"model_digest", "abc"}, {"scan_digest", "def"}, {"scan_units_to_metres", 0.001}};
    const scan_files::CachedResult cached(path, key);
    CHECK_FALSE(cached.find());  // nothing there yet
    const std::string text = cached.store({{"answer", 42}});
    CHECK(read_regular_file(path, 1u << 20) == text);
    const auto found = cached.find();
    REQUIRE(found);
    CHECK(found->at("answer") == 42);
    CHECK(found->at("key") == key);
    // The same key with its fields in another order: the same result.
    CHECK(scan_files::CachedResult(path, {{"scan_units_to_metres", 0.001}, {"scan_digest", "def"}, {"model_digest", "abc"}}).find());
    // Anything in the key changed: not this result.
    CHECK_FALSE(scan_files::CachedResult(path, {{"model_digest", "abc"}, {"scan_digest", "def"}, {"scan_units_to_metres", 0.01}}).find());
    CHECK_FALSE(scan_files::CachedResult(path, {{"model_digest", "abc"}, {"scan_digest", "xyz"}, {"scan_units_to_metres", 0.001}}).find());
    // The key under another field (a bootstrap round's "settings"): the field is what is compared.
    CHECK_FALSE(scan_files::CachedResult(path, key, "settings").find());
    // A key holding bytes that are not UTF-8 (a file name) is found as it was written (U+FFFD).
    const scan_files::CachedResult named(dir + "/named.json", {{"scan", std::string("caf\xe9.ply")}});
    named.store({{"done", true}});
    CHECK(named.find());
    // A malformed or truncated file is no result.
    std::ofstream(path, std::ios::trunc) << "{\"key\": {\"model_digest\": ";
    CHECK_FALSE(cached.find());
    std::ofstream(path, std::ios::trunc) << "[1, 2, 3]";
    CHECK_FALSE(cached.find());
    // Forgotten: gone.
    cached.store({{"answer", 43}});
    cached.forget();
    CHECK_FALSE(fs::exists(path));
    CHECK_FALSE(cached.find());
}

TEST_CASE("fit parameters are one format that reads its earlier versions and refuses what no fit is", "[scan_files]") {
    const Model& model = test::default_cpp_model();
    const uint32_t J = model.joint_count(), K = model.component_count();
    fitting::FitState fit;
    fit.shape.assign(K + model.segment_coefficient_count(), 0.0);
    for (std::size_t k = 0; k < fit.shape.size(); ++k) fit.shape[k] = 0.37 * std::sin(double(k) + 1);
    for (uint32_t j = 0; j < J; ++j) fit.pose.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * j + 0.1, Eigen::Vector3d(1, 2, 3).normalized())));
    fit.translation = Eigen::Vector3d(0.1, 0.9, -0.25);
    fit.scale = 1.0;
    const std::string digest = "0123456789abcdef";
    // Version 2, written and read: the same numbers, to the bit, the digest and model named.
    const nlohmann::ordered_json v2 = scan_files::fit_to_json(model, fit, digest);
    CHECK(v2.at("format") == scan_files::kFitParamsFormat);
    CHECK(v2.at("model_digest") == digest);
    const scan_files::FitParams back = scan_files::fit_params_from_json(nlohmann::ordered_json::parse(v2.dump()), model, digest);
    REQUIRE(back.frames.size() == 1);
    CHECK(back.frames[0].shape == fit.shape);
    CHECK(back.frames[0].translation == fit.translation);
    for (uint32_t j = 0; j < J; ++j) CHECK(back.frames[0].pose[j].coeffs() == fit.pose[j].coeffs());
    // Frames of a sequence share the shape.
    fitting::FitState second = fit;
    second.translation.x() += 1;
    CHECK(scan_files::fit_params_from_json(scan_files::fit_params_to_json(model, {fit, second}, digest), model, digest).frames[1].translation.x() == 1.1);
    // The layout of earlier registration reports and posture fits: one frame, rotations in joint order.
    nlohmann::ordered_json flat{{"shape", std::vector<double>(fit.shape.begin(), fit.shape.begin() + K)}, {"translation_m", {0.1, 0.9, -0.25}}, {"scale", 1.0},
                                {"segment_shape", std::vector<double>(fit.shape.begin() + K, fit.shape.end())}};
    std::vector<double> flat_rotations;
    for (const auto& q : fit.pose) flat_rotations.insert(flat_rotations.end(), {q.x(), q.y(), q.z(), q.w()});
    flat["rotations_xyzw"] = flat_rotations;
    const fitting::FitState old = scan_files::fit_from_json(flat, model);
    CHECK(old.shape == fit.shape);
    CHECK(old.pose[5].coeffs() == fit.pose[5].coeffs());
    // Version 1 (`sscape fit --params` before): floats, joints by name (the others at rest), no segments.
    const std::string name = model.data().skeleton.joint_names[3];
    nlohmann::ordered_json v1{{"format", "sscape fit parameters 1"}, {"model", model.data().metadata.name}, {"model_digest", digest}, {"shape", {0.5f, -0.25f}},
                              {"frames", {{{"rotations_xyzw", {{name, {0.0f, 0.0f, 0.6f, 0.8f}}}}, {"translation_m", {0.f, 1.f, 0.f}}, {"scale", 1.f}}}}};
    const fitting::FitState one = scan_files::fit_params_from_json(v1, model, digest).frames[0];
    CHECK(one.shape == std::vector<double>{0.5, -0.25});
    CHECK(one.pose[3].z() == double(0.6f));
    CHECK(one.pose[2].w() == 1.0);  // not named: at rest
    // Refused, naming why: another model, a later version, a joint the model lacks, segments that do
    // not match, values no fit gives.
    auto refused = [&](nlohmann::ordered_json j, const std::string& words) {
        try {
            scan_files::fit_params_from_json(j, model, digest);
            FAIL("accepted: " << words);
        } catch (const Error& e) {
            CHECK(e.status() == SSC_ERROR_INVALID_ARGUMENT);
            CHECK_THAT(std::string(e.what()), Catch::Matchers::Contains(words));
        }
    };
    nlohmann::ordered_json j = v1;
    j["model_digest"] = "ffffffffffffffff";
    refused(j, "fitted with the model");
    CHECK(scan_files::other_model(j, model, digest).find("not this one") != std::string::npos);
    CHECK(scan_files::other_model(v1, model, digest).empty());
    j = v1;
    j["format"] = "sscape fit parameters 3";
    refused(j, "is not one this sscape reads");
    j = v1;
    j["frames"][0]["rotations_xyzw"]["tail"] = {0, 0, 0, 1};
    refused(j, "no joint 'tail'");
    j = v2;
    j["segment_shape"] = {1.0};
    refused(j, "segment_shape needs the model's");
    j = v2;
    j["shape"][0] = 21;
    refused(j, "shape[0] is 21, outside");
    j = v2;
    j["frames"][0]["scale"] = 0.01;
    refused(j, "scale is 0.01");
    j = v2;
    j["frames"][0]["translation_m"][1] = 1e7;
    refused(j, "translation_m[1] is 10000000");
    j = v2;
    j["frames"] = nlohmann::ordered_json::array();
    refused(j, "frames needs 1 to 100000 frames");
}
