#include "learning/collection_scan.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/output_paths.hpp"
#include "common/rigid.hpp"
#include "io/readers.hpp"
#include "io/units.hpp"
#include "render/registration_picture.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <unordered_map>

namespace ssc::learning {

namespace fs = std::filesystem;

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

registration::Scan load_scan(const ScanInput& in, const Model& model, const ScanReading& reading, std::vector<std::string>* ignored) {
    registration::Scan scan;
    const Eigen::Matrix3d R = up_axis_rotation(reading.up);
    const io::PointFile pf = io::read_points(in.path);
    for (const auto& p : pf.points) scan.cloud.points.push_back(R * (p * reading.scan_units_to_metres));
    for (const auto& n : pf.normals) scan.cloud.normals.push_back(R * n);
    io::checked_body_span(in.path, scan.cloud.points, reading.scan_units_to_metres, reading.units_given);
    if (!in.landmarks.empty()) {
        std::unordered_map<std::string, uint32_t> by_name;
        const auto& marks = model.data().landmarks;
        for (uint32_t l = 0; l < marks.size(); ++l) by_name[io::normalized_landmark_name(marks[l].name)] = l;
        std::vector<Eigen::Vector3d> positions;
        for (const auto& r : io::read_lnd(in.landmarks)) {  // read_lnd: the file's numbers / 1000
            const auto it = by_name.find(io::normalized_landmark_name(r.name));
            if (it == by_name.end()) {
                if (ignored) ignored->push_back(r.name);
                continue;
            }
            positions.push_back(R * (r.position * (reading.lnd_units_to_metres * 1e3)));
            scan.landmarks.push_back({it->second, positions.back(), 1.0});
        }
        io::checked_body_span(in.landmarks, positions, reading.lnd_units_to_metres, reading.units_given);
    }
    return scan;
}

std::string scan_digest(const ScanInput& in) {
    std::string bytes = read_regular_file(in.path, 4ull << 30);
    if (!in.landmarks.empty()) bytes += read_regular_file(in.landmarks, 64ull << 20);
    return file_digest(bytes);
}

ScanFileResult register_scan_file(registration::Registrar& registrar, const std::string& model_digest, const ScanFileJob& job,
                                  const registration::RegistrationProgress& progress, ThreadPool* pool) {
    const Model& model = registrar.model();
    const ScanReading& reading = job.reading;
    const std::vector<std::string> inputs = {job.scan.path, job.scan.landmarks};
    for (const std::string& output : {job.mesh_path, record_report_path(job.mesh_path), fs::path(job.mesh_path).replace_extension(".failed.json").string(), job.picture_path})
        refuse_output_over_input(output, inputs);
    // The mesh, its report and the picture: all written, or none left (an unwritable report once
    // left the new mesh behind), and an unwritable path refused before the work.
    OutputFiles outputs({job.mesh_path, job.write_report ? record_report_path(job.mesh_path) : "", job.picture_path});
    ScanFileResult out;
    std::string digest;
    try {
        digest = scan_digest(job.scan);
    } catch (const Error& e) {  // an unreadable scan fails alone in a collection
        throw Error(SSC_ERROR_INVALID_ARGUMENT, e.what());
    }
    if (job.reuse && job.write_report && fs::exists(record_report_path(job.mesh_path))) {
        try {
            RegistrationRecord old = read_registration_record(job.mesh_path, model, false);
            if (old.model_digest == model_digest && old.scan_digest == digest && old.scan_units_to_metres == reading.scan_units_to_metres &&
                old.scan_up == reading.up && old.fit_segments == registrar.options().segments) {
                out.record = std::move(old);
                out.reused = true;
                registrar.forget_result();  // its result is not this job's
                return out;
            }
        } catch (const Error&) {
            // unreadable or from another model: made again below
        }
    }
    // A scan that failed with this model before fails again at once, with the same reason: a
    // resumed or distributed run does not pay for it twice.
    const std::string failure_path = fs::path(job.mesh_path).replace_extension(".failed.json").string();
    const bool memo = job.reuse && job.write_report;
    const nlohmann::json key{{"model_digest", model_digest}, {"scan_digest", digest}, {"scan_units_to_metres", reading.scan_units_to_metres},
                             {"scan_up", reading.up}, {"fit_segments", registrar.options().segments}};
    if (memo && fs::exists(failure_path)) {
        std::string reason;
        try {
            const nlohmann::json old = nlohmann::json::parse(read_regular_file(failure_path, 1u << 20));
            if (old.at("key") == key) reason = old.at("error").get<std::string>();
        } catch (const std::exception&) {
            reason.clear();  // unreadable: registered again
        }
        if (!reason.empty()) throw Error(SSC_ERROR_INVALID_ARGUMENT, reason);
    }
    std::vector<Eigen::Vector3d> points;
    const registration::Registration* result = nullptr;
    try {
        registration::Scan scan;
        try {
            scan = load_scan(job.scan, model, reading, &out.ignored_landmarks);
        } catch (const Error& e) {  // an unreadable or hostile scan fails alone
            throw Error(SSC_ERROR_INVALID_ARGUMENT, e.what());
        }
        out.points = scan.cloud.points.size();
        out.landmarks = scan.landmarks.size();
        if (!job.picture_path.empty()) points = scan.cloud.points;
        registrar.set_scan(std::move(scan.cloud), std::move(scan.triangles));
        registrar.set_landmarks(std::move(scan.landmarks));
        result = &registrar.run(progress, pool);
    } catch (const Error& e) {
        if (memo && e.status() == SSC_ERROR_INVALID_ARGUMENT) {
            const std::string text = nlohmann::json{{"key", key}, {"error", e.what()}}.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
            write_file_atomically(failure_path, text.data(), text.size());
        }
        throw;
    }
    if (memo && fs::exists(failure_path)) fs::remove(failure_path);
    const registration::Registration& r = *result;

    RegistrationRecord& rec = out.record;
    rec.scan = job.scan.path;
    rec.scan_units_to_metres = reading.scan_units_to_metres;
    rec.scan_up = reading.up;
    rec.fit_segments = registrar.options().segments;
    rec.seconds = r.report.seconds;
    rec.fit_seconds = r.report.fit_seconds;
    rec.rounds = r.report.rounds;
    rec.solves = r.report.solves;
    rec.valid = r.valid;
    rec.registered.name = job.mesh_path;
    rec.registered.vertices = r.vertices;
    if (!r.fit.frames.empty()) rec.registered.fit = r.fit.frames[0], rec.registered.has_fit = true;
    rec.quality = r.report.quality;
    rec.model_digest = model_digest;
    rec.scan_digest = digest;
    write_registration_record(job.mesh_path, model, rec, job.write_report);
    if (!job.picture_path.empty()) {
        const render::PictureFrame frame = rec.registered.has_fit ? render::fit_picture_frame(model, rec.registered.fit) : render::PictureFrame();
        render::write_registration_picture(job.picture_path, model, frame, points, rec.registered.vertices, rec.quality.vertex_distance);
    }
    // What is on disk from here on (floats in the scan's frame, distances to 0.01 mm): a run that
    // goes on from this record and one that resumes from the files then learn the same model.
    if (job.write_report) out.record = read_registration_record(job.mesh_path, model, false);
    outputs.keep();
    return out;
}

}  // namespace ssc::learning
