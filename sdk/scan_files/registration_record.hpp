// A registration on disk, as `sscape register` writes it and `sscape learn` and bootstrapping read
// it: the registered mesh (the template's topology, in the scan's frame and units) and its JSON
// report beside it (the mesh's path with .json): the scan's units and up axis, times, quality
// overall and per body region, the model fit that started it, and (bootstrapping) the digest of the
// model it was registered with and each vertex's distance to the scan.
#pragma once

#include "fitting/kinematics.hpp"
#include "registration/registration_quality.hpp"
#include "synthesis/model.hpp"

#include <string>

namespace ssc::scan_files {

// One registered scan: the template's vertices on the scan (model frame: metres, +Y up) and the
// model fit that started the registration (needed by Posture::Skeleton).
struct RegisteredScan {
    std::string name;
    std::vector<Eigen::Vector3d> vertices;
    bool has_fit = false;
    fitting::FitState fit;
};

struct RegistrationRecord {
    std::string scan;                 // the scan's file
    double scan_units_to_metres = 1;  // the scan's units
    std::string scan_up = "y";        // the scan's axis that is the model's +Y
    bool fit_segments = false;        // the model fit had the segment shape spaces (RegistrationOptions::segments)
    double seconds = 0, fit_seconds = 0;
    uint32_t rounds = 0, solves = 0;  // the deformation's stiffness rounds and linear solves
    std::vector<uint8_t> valid;       // per vertex: ended on a compatible scan point (empty when unknown)
    RegisteredScan registered;        // the model frame (metres, +Y up); name: the mesh's path
    registration::RegistrationQuality quality;  // vertex_distance may be empty
    std::string model_digest;         // empty when unknown
    std::string scan_digest;          // of the scan file's bytes; empty when unknown
};

// The report's path for a registered mesh.
std::string record_report_path(const std::string& mesh_path);

// What a record's files hold, byte for byte: the mesh and the report's text (empty without one).
struct RecordBytes {
    std::string mesh, report;
};

// Writes the mesh (.ply or .obj, by extension) then (with_report) the report, each atomically: a
// report on disk means its mesh is complete. Returns the bytes written. Throws ssc::Error (IO).
RecordBytes write_registration_record(const std::string& mesh_path, const Model& model, const RegistrationRecord& record, bool with_report = true);

// Reads a mesh and its report. Throws ssc::Error (IO for a missing or unreadable file;
// INVALID_ARGUMENT for a malformed report, a mesh of another vertex count, or a report without
// the model fit when need_fit).
RegistrationRecord read_registration_record(const std::string& mesh_path, const Model& model, bool need_fit);

// A record from its files' bytes (mesh_path names the mesh and says its format): what
// read_registration_record gives for those files, without reading them. Throws as it.
RegistrationRecord registration_record_from_bytes(const std::string& mesh_path, const RecordBytes& bytes, const Model& model, bool need_fit);

// The report alone, from its text (`path` names it in messages): every value range-checked, the
// mesh's vertices not read (what the fuzz target feeds). Throws as read_registration_record.
RegistrationRecord parse_registration_report(const std::string& text, const std::string& path, const Model& model, bool need_fit);

// A short digest of a file's bytes (hex): which model and which scan a registration was made from.
std::string model_digest(const std::vector<unsigned char>& model_file);
std::string file_digest(const std::string& bytes);

}  // namespace ssc::scan_files
