// One scan of a collection, from its files to its registration on disk: the scans of a folder
// (with their landmark files), a scan read in the model's frame, and the registration written as a
// record (registration_record.hpp) unless a current one is already there. `sscape register`,
// bootstrapping and the C API's file jobs (the Python pipeline's tasks) all register through
// register_scan_file, so each gives the same files for the same scan and model.
#pragma once

#include "learning/registration_record.hpp"
#include "registration/registrar.hpp"

#include <string>
#include <vector>

namespace ssc {
class ThreadPool;
}

namespace ssc::learning {

struct ScanInput {
    std::string name;       // unique in a collection; names its files (the scan file's stem)
    std::string path;       // PLY or OBJ
    std::string landmarks;  // a CAESAR .lnd on the scan, or empty
};

// How a collection's files are read: their units and the axis that is up.
struct ScanReading {
    double scan_units_to_metres = 1;    // the scans' units (metres by default)
    double lnd_units_to_metres = 1e-3;  // the landmark files' (the .lnd format's millimetres by default)
    std::string up = "y";               // x, y, z, -x, -y or -z
    bool units_given = false;           // for messages: the units were chosen, not defaulted
};

// A reading with both files in `units` (empty: the defaults) and the given up axis (empty: y).
// INVALID_ARGUMENT for unknown units or axes.
ScanReading scan_reading(const std::string& units, const std::string& up);

// Every .ply and .obj in the folder, sorted by name; landmarks NAME.lnd beside a scan (or, for the
// simulator's PREFIX_scan.ply, PREFIX.lnd). IO for a folder that cannot be listed. An entry named
// as a scan that cannot be one (a link to nothing, a loop of links, no permission to look) is left
// out and, with skipped, listed as "PATH: why" in name order: one stale link must not stop a
// collection.
std::vector<ScanInput> find_scans(const std::string& folder, std::vector<std::string>* skipped = nullptr);

// The scan in the model's frame (metres, +Y up) with its landmarks matched to the model's by name
// (names not in the model are listed in `ignored`). INVALID_ARGUMENT for a malformed file or one
// whose extent, read in these units, is no body (5 cm to 3 m; the message says which units fit);
// IO for an unreadable one.
registration::Scan load_scan(const ScanInput& in, const Model& model, const ScanReading& reading,
                             std::vector<std::string>* ignored = nullptr);

// The digest of the scan file's bytes and its landmark file's: a changed file is registered again.
// IO for an unreadable file.
std::string scan_digest(const ScanInput& in);

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

}  // namespace ssc::learning
