#include "learning/posture_fit.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "fitting/solver.hpp"
#include "scan_files/cached_result.hpp"
#include "scan_files/fit_params.hpp"
#include "scan_files/registration_record.hpp"
#include "sscape_format/model_io.hpp"

#include <filesystem>

namespace ssc::learning {

namespace fs = std::filesystem;

std::string posture_fit_path(const std::string& out_dir, const std::string& scan_name) {
    return (fs::path(out_dir) / "posture_fits" / (scan_name + ".json")).string();
}

void check_posture_model(const format::ModelData& t, const format::ModelData& p) {
    const bool same = t.mesh.vertex_count == p.mesh.vertex_count && t.mesh.triangles == p.mesh.triangles &&
                      t.skeleton.joint_names == p.skeleton.joint_names && t.skeleton.parents == p.skeleton.parents &&
                      t.skeleton.rest_orientations == p.skeleton.rest_orientations && t.skin.joints == p.skin.joints && t.skin.weights == p.skin.weights;
    SSC_REQUIRE_ARG(same, "the posture model '" + p.metadata.name + "' does not share the mesh, skeleton and skinning of the model '" + t.metadata.name +
                              "' (its poses would not unpose that model's registrations)");
}

format::ModelData read_posture_model(const std::vector<unsigned char>& file) {
    try {
        return format::read_model(file.data(), file.size());
    } catch (const Error& e) {
        throw Error(SSC_ERROR_INVALID_ARGUMENT, std::string("the posture model: ") + e.what());
    }
}

PostureModel::PostureModel(const std::vector<unsigned char>& file, const registration::RegistrationOptions& options)
    : data_(std::make_shared<const format::ModelData>(read_posture_model(file))),
      runtime_(format::ModelData(*data_), &heap_),
      lin_(runtime_.model(), runtime_.model().component_count(), runtime_.anatomy(), options.segments, options.segments_left_out),
      options_(options),
      digest_(scan_files::model_digest(file)) {}

fitting::FitState PostureModel::fit(const scan_files::ScanInput& scan, const scan_files::ScanReading& reading, const std::string& path, const fitting::FitState* known,
                                    ThreadPool* pool, bool* reused) const {
    const Model& model = runtime_.model();
    if (reused) *reused = false;
    scan_files::ScanBytes bytes;  // read once: the key's digest names the bytes fitted
    try {
        bytes = scan_files::read_scan_bytes(scan);
    } catch (const Error& e) {  // an unreadable scan fails alone in a collection
        throw Error(SSC_ERROR_INVALID_ARGUMENT, e.what());
    }
    const std::string digest = scan_files::scan_digest(bytes);
    const scan_files::CachedResult kept(path, {{"model_digest", digest_}, {"scan_digest", digest}, {"scan_units_to_metres", reading.scan_units_to_metres},
                                               {"scan_up", reading.up}, {"fit_segments", options_.segments}});
    if (const auto old = kept.find()) {
        try {
            const fitting::FitState f = scan_files::fit_from_json(old->at("fit"), model);
            if (reused) *reused = true;
            return f;
        } catch (const std::exception&) {
            // not a fit of this model: fitted again below
        }
    }
    fitting::FitState made;
    if (known) {
        made = *known;
    } else {
        registration::Scan s;
        try {
            s = scan_files::parse_scan(bytes, scan, model, reading);
            bytes = scan_files::ScanBytes();
        } catch (const Error& e) {
            throw Error(SSC_ERROR_INVALID_ARGUMENT, e.what());
        }
        fitting::Frame frame;
        frame.landmarks = std::move(s.landmarks);
        frame.clouds.push_back(std::move(s.cloud));
        const fitting::FitSolution solution = fitting::fit(lin_, {frame}, options_.fit, nullptr, {}, pool);
        SSC_REQUIRE_ARG(!solution.frames.empty(), scan.name + ": the posture model could not be fitted to the scan");
        made = solution.frames[0];
    }
    fs::create_directories(fs::path(path).parent_path());
    const std::string text = kept.store({{"scan", scan.path}, {"fit", scan_files::fit_to_json(model, made, digest_)}});
    // What is on disk (as a resumed run reads it), so both learn the same model.
    return scan_files::fit_from_json(nlohmann::ordered_json::parse(text).at("fit"), model);
}

}  // namespace ssc::learning
