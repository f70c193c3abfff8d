// Scan files of a collection (sscape_offline.h): a folder's scans, and one scan file registered
// into its record on disk (scan_files/scan_input.hpp does the work).
#include "capi/guard.hpp"
#include "capi/cpp_access.hpp"
#include "capi/registration_report.hpp"
#include "scan_files/register_scan_file.hpp"
#include <sscape/sscape_offline.h>

#include <algorithm>

using namespace ssc;
using namespace ssc::capi;

struct ssc_scan_list {
    std::vector<scan_files::ScanInput> scans;
    std::vector<std::string> skipped_paths, skipped_reasons;  // entries left out (find_scans), in name order
};

extern "C" {

ssc_status ssc_scan_list_create(const char* folder, ssc_scan_list** out) {
    return guarded(__func__, [&] {
        need(folder, "folder");
        need(out, "out");
        auto list = std::make_unique<ssc_scan_list>();
        std::vector<std::string> skipped;
        list->scans = scan_files::find_scans(folder, &skipped);
        for (const std::string& entry : skipped) {  // "PATH: why"; the path may hold ": " too, the reason does not
            const std::size_t colon = entry.rfind(": ");
            list->skipped_paths.push_back(entry.substr(0, colon));
            list->skipped_reasons.push_back(colon == std::string::npos ? std::string() : entry.substr(colon + 2));
        }
        *out = list.release();
    });
}

uint32_t ssc_scan_list_skipped_count(const ssc_scan_list* list) { return list ? uint32_t(list->skipped_paths.size()) : 0; }

ssc_status ssc_scan_list_get_skipped(const ssc_scan_list* list, uint32_t index, const char** path, const char** reason) {
    return guarded(__func__, [&] {
        need(list, "list");
        SSC_REQUIRE_ARG_S(index < list->skipped_paths.size(), "index " << index << " is beyond the " << list->skipped_paths.size() << " entries skipped");
        if (path) *path = list->skipped_paths[index].c_str();
        if (reason) *reason = list->skipped_reasons[index].c_str();
    });
}

void ssc_scan_list_destroy(ssc_scan_list* list) { delete list; }

uint32_t ssc_scan_list_count(const ssc_scan_list* list) { return list ? uint32_t(list->scans.size()) : 0; }

ssc_status ssc_scan_list_get(const ssc_scan_list* list, uint32_t index, const char** name, const char** path, const char** landmarks) {
    return guarded(__func__, [&] {
        need(list, "list");
        SSC_REQUIRE_ARG_S(index < list->scans.size(), "index " << index << " is beyond the " << list->scans.size() << " scans");
        const scan_files::ScanInput& s = list->scans[index];
        if (name) *name = s.name.c_str();
        if (path) *path = s.path.c_str();
        if (landmarks) *landmarks = s.landmarks.c_str();
    });
}

void ssc_scan_file_job_init(ssc_scan_file_job* job, size_t size) {
    if (!job || size < sizeof(uint32_t)) return;
    ssc_scan_file_job j{};
    j.struct_size = static_cast<uint32_t>(size < sizeof j ? size : sizeof j);
    j.write_report = 1;
    std::memcpy(job, &j, j.struct_size);
}

ssc_status ssc_registration_run_file(ssc_registration* registration, const ssc_scan_file_job* job, ssc_stage_progress_fn progress, void* user,
                                     ssc_registration_report* report, uint32_t* out_reused) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        need(job, "job");
        const ssc_scan_file_job j = read_def(job, ssc_scan_file_job_init, "job");
        need(j.scan_path, "job->scan_path");
        need(j.mesh_path, "job->mesh_path");
        if (report)
            SSC_REQUIRE_ARG(report->struct_size >= sizeof(uint32_t), "report->struct_size must be set to sizeof(ssc_registration_report)");
        scan_files::ScanFileJob work;
        work.scan.path = j.scan_path;
        work.scan.landmarks = optional_string(j.landmarks_path);
        work.reading = scan_files::scan_reading(optional_string(j.units), optional_string(j.up));
        work.mesh_path = j.mesh_path;
        work.write_report = j.write_report != 0;
        work.reuse = j.reuse != 0;
        SSC_REQUIRE_ARG(!work.reuse || work.write_report, "job->reuse needs job->write_report: a registration is reused by its report");
        work.picture_path = optional_string(j.picture_path);
        registration::RegistrationProgress cb;
        if (progress) cb = [&](const char* stage, uint32_t done, uint32_t total) { return progress(user, stage, done, total) == 0; };
        registration::Registrar& registrar = registrar_of(registration);
        const ssc_model* model = model_of(registration);
        const scan_files::ScanFileResult r = scan_files::register_scan_file(registrar, digest_of(model), work, cb, &pool_of(model));
        const scan_files::RegistrationRecord& rec = r.record;
        if (report)
            write_report(rec.rounds, rec.solves, std::size_t(std::count(rec.valid.begin(), rec.valid.end(), uint8_t(1))), rec.seconds,
                         rec.fit_seconds, rec.quality, r.reused ? rec.quality.scan_to_registration.count : r.points, r.landmarks, report);
        const std::size_t most = registrar.options().max_scan_points;
        if (!r.reused && r.points > most)
            log_message(model, SSC_LOG_WARNING, std::string(j.scan_path) + ": " + std::to_string(r.points) + " points; registered from " +
                                                                       std::to_string(most) + " of them, evenly spread (the registration's memory bound)");
        for (const auto& name : r.ignored_landmarks)
            log_message(model, SSC_LOG_WARNING, std::string(j.landmarks_path) + ": landmark '" + name + "' is not one of the model's; ignored");
        if (out_reused) *out_reused = r.reused ? 1 : 0;
    });
}

}  // extern "C"
