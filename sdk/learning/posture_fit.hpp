// Posture fits: the pose that Posture::Skeleton unposes a registration with, taken from a fit of a
// posture model to the registration's scan instead of from the fit that started the registration.
// A model learned from posed registrations keeps some posture in its shape space, so its fits turn
// limbs to make up for shape they cannot follow; a model learned from bodies at rest (the built-in
// one) poses them about twice as well, and the learned model comes closer to one learned from the
// true rest bodies (docs/learning.md, "Posture fits").
//
// Bootstrapping fits each scan once per posture model and keeps the fit on disk:
//   posture_fits/NAME.json   the fit, and the digests of the model and the scan it was made from
#pragma once

#include "scan_files/scan_input.hpp"
#include "registration/register_scan.hpp"
#include "runtime/runtime_model.hpp"

#include <memory>

#include <string>

namespace ssc {
class ThreadPool;
}

namespace ssc::learning {

// Where bootstrapping keeps a scan's posture fit.
std::string posture_fit_path(const std::string& out_dir, const std::string& scan_name);

// A posture model's file bytes read; ssc::Error (INVALID_ARGUMENT, saying it is the posture
// model) for a bad file.
format::ModelData read_posture_model(const std::vector<unsigned char>& file);

// Throws ssc::Error (INVALID_ARGUMENT) unless `posture` shares the template's mesh (vertex count,
// triangles), skeleton (joint names, parents, rest orientations) and skinning: the poses of one
// must unpose the other's registrations.
void check_posture_model(const format::ModelData& template_model, const format::ModelData& posture);

// A posture model loaded to fit scans: its file's bytes read (ssc::Error, INVALID_ARGUMENT for a
// bad model) and built as a registrar builds its model, with the registration's fit options and
// segment setting. Immutable after construction; fit() may run on several threads at once.
class PostureModel {
public:
    PostureModel(const std::vector<unsigned char>& file, const registration::RegistrationOptions& options);
    PostureModel(const PostureModel&) = delete;
    PostureModel& operator=(const PostureModel&) = delete;

    const std::shared_ptr<const format::ModelData>& data() const { return data_; }  // for LearnSpec::posture_model
    const std::string& digest() const { return digest_; }

    // The model fitted to the scan as registration's model initialisation fits it, written to
    // `path` atomically; or the fit already there when it was made from the same model, scan file
    // and landmarks, units, up axis and segment setting (*reused set). `known`: a fit of this model
    // to this scan already made (the registration's, when a round registered with the posture
    // model), written instead of fitting again. Throws ssc::Error: INVALID_ARGUMENT for a scan that
    // cannot be read or fitted, IO.
    fitting::FitState fit(const scan_files::ScanInput& scan, const scan_files::ScanReading& reading, const std::string& path, const fitting::FitState* known = nullptr,
                          ThreadPool* pool = nullptr, bool* reused = nullptr) const;

private:
    const Allocator heap_;
    std::shared_ptr<const format::ModelData> data_;
    RuntimeModel runtime_;
    fitting::LinearModel lin_;
    registration::RegistrationOptions options_;
    std::string digest_;
};

}  // namespace ssc::learning
