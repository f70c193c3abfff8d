// The scan-file stage (sdk/scan_files): a scan read once (its digest names the bytes it is parsed
// from) and results kept on disk with their key (CachedResult).
#include "support.hpp"

#include "common/files.hpp"
#include "scan_files/cached_result.hpp"
#include "scan_files/scan_input.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace ssc;
namespace fs = std::filesystem;

namespace {

std::string fresh_folder(const std::string& name) {
    const fs::path p = fs::current_path() / "scan_files" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
}

// An ASCII PLY of n points on a 1.7 m tall column, shifted by dx: a body's extent.
void write_column(const std::string& path, int n, double dx) {
    std::ofstream f(path);
    f << "ply\nformat ascii 1.0\nelement vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (int i = 0; i < n; ++i) f << dx + 0.1 * (i % 3) << " " << 1.7 * i / (n - 1) << " " << 0.05 * (i % 5) << "\n";
}

}  // namespace

TEST_CASE("a scan is parsed from the bytes its digest was taken of", "[scan_files]") {
    const std::string dir = fresh_folder("read_once");
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
    const std::string dir = fresh_folder("cached");
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
