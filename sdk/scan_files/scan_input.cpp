#include "scan_files/scan_input.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/rigid.hpp"
#include "io/readers.hpp"
#include "io/units.hpp"

#include <algorithm>
#include <filesystem>
#include <unordered_map>

namespace ssc::scan_files {

namespace fs = std::filesystem;

// A landmark file is a few kilobytes; the bound keeps a hostile one from filling memory.
constexpr uint64_t kMaxLandmarkBytes = 64ull << 20;

ScanReading scan_reading(const std::string& units, const std::string& up) {
    ScanReading r;
    if (!units.empty()) r.scan_units_to_metres = r.lnd_units_to_metres = io::units_to_metres(units), r.units_given = true;
    if (!up.empty()) {
        const std::vector<std::string> axes = {"x", "y", "z", "-x", "-y", "-z"};
        SSC_REQUIRE_ARG(std::find(axes.begin(), axes.end(), up) != axes.end(), "the up axis '" + up + "' is none of x, y, z, -x, -y, -z");
        r.up = up;
    }
    return r;
}

std::vector<ScanInput> find_scans(const std::string& folder, std::vector<std::string>* skipped) {
    std::vector<ScanInput> out;
    std::vector<std::string> left_out;
    std::error_code ec;
    fs::directory_iterator it(folder, ec);
    if (ec) throw Error(SSC_ERROR_IO, folder + ": cannot list the folder: " + ec.message());
    for (const auto& entry : it) {
        // Hidden files are no scans: temporaries, a copier's "._" resource forks.
        if (entry.path().filename().string().rfind('.', 0) == 0) continue;
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (ext != ".ply" && ext != ".obj") continue;
        // The status through links, without throwing: a loop of links (ELOOP) once aborted the
        // whole listing as an internal error.
        std::error_code status_error;
        const fs::file_status status = fs::status(entry.path(), status_error);
        if (status_error && status_error != std::errc::no_such_file_or_directory) {
            left_out.push_back(entry.path().string() + ": " + status_error.message());
            continue;
        }
        if (status.type() == fs::file_type::not_found) {
            left_out.push_back(entry.path().string() + ": a link to nothing");
            continue;
        }
        if (status.type() != fs::file_type::regular) continue;  // a folder named like a scan: not one
        ScanInput s;
        s.name = entry.path().stem().string();
        s.path = entry.path().string();
        fs::path lnd = entry.path();
        lnd.replace_extension(".lnd");
        const std::string suffix = "_scan";
        std::error_code lnd_error;
        if (!fs::exists(lnd, lnd_error) && s.name.size() > suffix.size() && s.name.compare(s.name.size() - suffix.size(), suffix.size(), suffix) == 0)
            lnd = entry.path().parent_path() / (s.name.substr(0, s.name.size() - suffix.size()) + ".lnd");
        if (fs::exists(lnd, lnd_error)) s.landmarks = lnd.string();
        out.push_back(s);
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    std::sort(left_out.begin(), left_out.end());
    if (skipped) *skipped = std::move(left_out);
    return out;
}

ScanBytes read_scan_bytes(const ScanInput& in) {
    ScanBytes b;
    b.scan = read_regular_file(in.path, io::kMaxInputBytes);
    if (!in.landmarks.empty()) b.landmarks = read_regular_file(in.landmarks, kMaxLandmarkBytes);
    return b;
}

std::string scan_digest(const ScanBytes& bytes) {
    if (bytes.landmarks.empty()) return content_digest(bytes.scan.data(), bytes.scan.size());
    const std::string both = bytes.scan + bytes.landmarks;
    return content_digest(both.data(), both.size());
}

registration::Scan parse_scan(const ScanBytes& bytes, const ScanInput& in, const Model& model, const ScanReading& reading,
                              std::vector<std::string>* ignored) {
    registration::Scan scan;
    const Eigen::Matrix3d R = up_axis_rotation(reading.up);
    const io::PointFile pf = io::parse_points(bytes.scan, in.path);
    for (const auto& p : pf.points) scan.cloud.points.push_back(R * (p * reading.scan_units_to_metres));
    for (const auto& n : pf.normals) scan.cloud.normals.push_back(R * n);
    io::checked_body_span(in.path, scan.cloud.points, reading.scan_units_to_metres, reading.units_given);
    if (!in.landmarks.empty()) {
        std::vector<Eigen::Vector3d> positions;
        for (const auto& [index, r] : match_landmarks(io::parse_lnd(bytes.landmarks, in.landmarks), model.data(), ignored)) {  // the file's numbers / 1000
            positions.push_back(R * (r.position * (reading.lnd_units_to_metres * 1e3)));
            scan.landmarks.push_back({index, positions.back(), 1.0});
        }
        io::checked_body_span(in.landmarks, positions, reading.lnd_units_to_metres, reading.units_given);
    }
    return scan;
}

std::vector<std::pair<uint32_t, io::LandmarkRecord>> match_landmarks(const std::vector<io::LandmarkRecord>& records, const format::ModelData& model,
                                                                      std::vector<std::string>* unknown) {
    std::unordered_map<std::string, uint32_t> by_name;
    for (uint32_t l = 0; l < model.landmarks.size(); ++l) by_name[io::normalized_landmark_name(model.landmarks[l].name)] = l;
    std::vector<std::pair<uint32_t, io::LandmarkRecord>> matched;
    for (const io::LandmarkRecord& r : records) {
        const auto it = by_name.find(io::normalized_landmark_name(r.name));
        if (it != by_name.end()) matched.emplace_back(it->second, r);
        else if (unknown) unknown->push_back(r.name);
    }
    return matched;
}

registration::Scan load_scan(const ScanInput& in, const Model& model, const ScanReading& reading, std::vector<std::string>* ignored) {
    return parse_scan(read_scan_bytes(in), in, model, reading, ignored);
}

}  // namespace ssc::scan_files
