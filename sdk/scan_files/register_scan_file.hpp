// One scan file registered into its record on disk (registration_record.hpp), unless a current
// record is already there. `sscape register`, bootstrapping and the C API's file jobs (the Python
// pipeline's tasks) all register through register_scan_file, so each gives the same files for the
// same scan and model.
#pragma once

#include "registration/registrar.hpp"
#include "scan_files/registration_record.hpp"
#include "scan_files/scan_input.hpp"

#include <string>
#include <vector>

namespace ssc {
class ThreadPool;
}

namespace ssc::scan_files {

struct ScanFileJob {
    ScanInput scan;
    ScanReading reading;
    std::string mesh_path;     // the registered mesh, .ply or .obj
    bool write_report = true;  // the report beside the mesh (record_report_path)
    bool reuse = false;        // keep a record made from the same model, scan, landmarks, units, up and fit_segments
    std::string picture_path;  // a PNG of the scan beside the registration, or empty
};

struct ScanFileResult {
    RegistrationRecord record;
    bool reused = false;
    std::size_t points = 0, landmarks = 0;  // read from the files (0 when reused)
    std::vector<std::string> ignored_landmarks;
};

// Registers the scan with the registrar's model (model_digest: its file's digest, recorded for
// reuse) and writes the record atomically; with job.reuse, first returns a current record already
// on disk without registering, and a scan that could not be registered with this model before
// (NAME.failed.json beside the mesh) fails again at once with the same reason. The registrar keeps the result (not when reused). Throws
// ssc::Error: INVALID_ARGUMENT for a scan that cannot be read as a body or registered, IO,
// CANCELLED (nothing written).
ScanFileResult register_scan_file(registration::Registrar& registrar, const std::string& model_digest, const ScanFileJob& job,
                                  const registration::RegistrationProgress& progress = {}, ThreadPool* pool = nullptr);

}  // namespace ssc::scan_files
