#include "scan_files/register_scan_file.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/output_paths.hpp"
#include "render/registration_picture.hpp"
#include "scan_files/cached_result.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace ssc::scan_files {

namespace fs = std::filesystem;

namespace {

nlohmann::ordered_json registration_key(const std::string& model_digest, const std::string& scan_digest, double units_to_metres, const std::string& up,
                                        bool fit_segments) {
    return {{"model_digest", model_digest}, {"scan_digest", scan_digest}, {"scan_units_to_metres", units_to_metres}, {"scan_up", up},
            {"fit_segments", fit_segments}};
}

nlohmann::ordered_json registration_key(const std::string& model_digest, const std::string& scan_digest, const ScanReading& reading, bool fit_segments) {
    return registration_key(model_digest, scan_digest, reading.scan_units_to_metres, reading.up, fit_segments);
}

}  // namespace

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
    // The files read once: the digest names the bytes the scan is parsed from.
    ScanBytes bytes;
    try {
        bytes = read_scan_bytes(job.scan);
    } catch (const Error& e) {  // an unreadable scan fails alone in a collection
        throw Error(SSC_ERROR_INVALID_ARGUMENT, e.what());
    }
    const std::string digest = scan_digest(bytes);
    // What a registration is made from: a record or a failure with the same key is this job's.
    const nlohmann::ordered_json key = registration_key(model_digest, digest, reading, registrar.options().segments);
    if (job.reuse && job.write_report && fs::exists(record_report_path(job.mesh_path))) {
        try {
            RegistrationRecord old = read_registration_record(job.mesh_path, model, false);
            if (registration_key(old.model_digest, old.scan_digest, old.scan_units_to_metres, old.scan_up, old.fit_segments) == key) {
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
    const bool memo = job.reuse && job.write_report;
    const CachedResult failure(fs::path(job.mesh_path).replace_extension(".failed.json").string(), key);
    if (memo)
        if (const auto old = failure.find(); old && old->contains("error") && old->at("error").is_string() && !old->at("error").get<std::string>().empty())
            throw Error(SSC_ERROR_INVALID_ARGUMENT, old->at("error").get<std::string>());
    std::vector<Eigen::Vector3d> points;
    const registration::Registration* result = nullptr;
    try {
        registration::Scan scan;
        try {
            scan = parse_scan(bytes, job.scan, model, reading, &out.ignored_landmarks);
            bytes = ScanBytes();  // the registration's memory, not the file's
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
        if (memo && e.status() == SSC_ERROR_INVALID_ARGUMENT) failure.store({{"error", e.what()}});
        throw;
    }
    if (memo) failure.forget();
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
    const RecordBytes written = write_registration_record(job.mesh_path, model, rec, job.write_report);
    if (!job.picture_path.empty()) {
        const render::PictureFrame frame = rec.registered.has_fit ? render::fit_picture_frame(model, rec.registered.fit) : render::PictureFrame();
        render::write_registration_picture(job.picture_path, model, frame, points, rec.registered.vertices, rec.quality.vertex_distance);
    }
    // What is on disk from here on (floats in the scan's frame, distances to 0.01 mm), parsed from
    // the bytes written: a run that goes on from this record and one that resumes from the files
    // then learn the same model.
    if (job.write_report) out.record = registration_record_from_bytes(job.mesh_path, written, model, false);
    outputs.keep();
    return out;
}

}  // namespace ssc::scan_files
