// A scan's files as the offline tools take them: the scans of a folder (with their landmark
// files), how their units and up axis are read, and one scan read once: its bytes, their digest
// (what reuse goes by) and the scan parsed from those same bytes in the model's frame.
#pragma once

#include "io/readers.hpp"
#include "registration/register_scan.hpp"
#include "synthesis/model.hpp"

#include <string>
#include <vector>

namespace ssc::scan_files {

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

// A scan's files as read from disk, once: the digest is taken of these bytes and the scan parsed
// from them, so the scan registered is the scan the digest names.
struct ScanBytes {
    std::string scan;       // the scan file's bytes
    std::string landmarks;  // the landmark file's, empty without one
};

// IO for an unreadable file or one past the readers' size bound.
ScanBytes read_scan_bytes(const ScanInput& in);

// The digest of the scan file's bytes and its landmark file's: a changed file is registered again.
std::string scan_digest(const ScanBytes& bytes);

// The scan in the model's frame (metres, +Y up) with its landmarks matched to the model's by name
// (names not in the model are listed in `ignored`), parsed from its bytes (`in` names the files in
// messages and says by its extension how the scan is written). INVALID_ARGUMENT for a malformed
// file or one whose extent, read in these units, is no body (5 cm to 3 m; the message says which
// units fit).
registration::Scan parse_scan(const ScanBytes& bytes, const ScanInput& in, const Model& model, const ScanReading& reading,
                              std::vector<std::string>* ignored = nullptr);

// A landmark file's records matched to the model's landmarks by name (io::normalized_landmark_name:
// case, spaces and punctuation ignored), in file order: the model's landmark index and the record.
// The names the model lacks are added to `unknown`. parse_scan and the fitter's landmark files
// (ssc_fitter_add_landmarks_file) match through here.
std::vector<std::pair<uint32_t, io::LandmarkRecord>> match_landmarks(const std::vector<io::LandmarkRecord>& records, const format::ModelData& model,
                                                                      std::vector<std::string>* unknown = nullptr);

// read_scan_bytes then parse_scan, for a caller that needs no digest.
registration::Scan load_scan(const ScanInput& in, const Model& model, const ScanReading& reading,
                             std::vector<std::string>* ignored = nullptr);

}  // namespace ssc::scan_files
