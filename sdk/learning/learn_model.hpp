// Learning a model from registered scans: the registrations (the template's topology, from
// `sscape register`) brought to one posture, aligned, and summarised by PCA; everything else
// (mesh, skeleton, skinning, landmarks, vertex sets, joint limits and roles) carried over from the
// model they were registered with; the attribute model learned again from the new bodies.
#pragma once

#include "learning/posture_normalization.hpp"
#include "scan_files/registration_record.hpp"
#include "sscape_format/model_data.hpp"
#include "training/attributes.hpp"
#include "training/pca.hpp"
#include "training/segment_shapes.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ssc::learning {

struct LearnSpec {
    uint32_t components = 20;        // at most bodies - 1
    Posture posture = Posture::Skeleton;
    // Procrustes with scale: every body brought to the collection's average size first, so the
    // shape space holds proportions only (the paper's option; stature is then not in the model).
    bool scale = false;
    // Known per-scan attributes (sex, age, ...), each with one value per scan in input order.
    std::vector<training::KnownAttribute> attributes;
    std::string name = "sscape-learned";
    std::string provenance;           // what the caller knows of the inputs (files, settings)
    // The learned model's licence is its scans' owner's to give, not the template's.
    std::string license = "unspecified (set by the owner of the scans)";
    double tolerance = 1e-4;          // basis quantization bound, metres
    uint32_t seed = 1;                // randomized SVD
    // Segment shape spaces (head, arms, torso, legs) beside the whole body's: components per segment,
    // 0 for none. The template needs the body-part vertex sets (see training::segment_layout).
    uint32_t segment_components = 0;
    double segment_band = 0.08;       // metres on each side of a segment border
    uint32_t threads = 0;             // posture normalization's worker threads; 0: every hardware thread
    // Posture::Skeleton: the scans' fits are this model's (posture_fit.hpp), not the template's, and
    // each registration is unposed with its skeleton; it must share the template's mesh, skeleton
    // and skinning. Null: the template's own fits.
    std::shared_ptr<const format::ModelData> posture_model;
};

struct LearnReport {
    uint32_t bodies = 0, components = 0;
    std::vector<double> stddev;      // per component: the body's 3V coordinates' displacement at 1 SD, metres (norm)
    double total_variance = 0;       // m^2 per body
    double explained = 0;            // share of the variance the kept components hold
    double quantization_error = 0;   // metres
    // Attributes that are sliders, and those that could not be (dependent on the ones before them,
    // or more sliders than components): attributes only.
    std::vector<std::string> sliders, not_sliders;
    // Per segment, when learned: its own components' share of its variance beside the whole body's.
    std::vector<training::SegmentCompactness> segments;
};

using LearnProgress = std::function<void(const std::string& stage)>;

// The registrations as learning sees them, one body per row (3V: x y z per vertex): brought to the
// rest posture (posture normalization with the model they were registered with), Procrustes
// aligned, and moved as one onto the model's mean standing on its ground. Throws ssc::Error
// (INVALID_ARGUMENT) for a scan of another vertex count, or without its fit for Posture::Skeleton.
// The bodies are normalized on `threads` threads (0: every hardware thread); the result does not
// depend on the count. posture_model: Posture::Skeleton unposes with its skeleton (the scans' fits
// are its fits; it shares the model's mesh and rig); null: the model's.
training::SampleMatrix normalized_bodies(const Model& model, const std::vector<scan_files::RegisteredScan>& scans, Posture posture, bool scale = false,
                                         uint32_t threads = 0, const Model* posture_model = nullptr);

// Throws ssc::Error (INVALID_ARGUMENT) for fewer than 3 scans, a scan of another vertex count,
// non-finite vertices, Posture::Skeleton with a scan lacking its fit, components (or segment components)
// outside [1, bodies - 1], segments on a template without the body-part vertex sets, attributes without one finite value per scan, or a
// posture model that does not share the template's mesh and rig.
format::ModelData learn_model(const format::ModelData& template_model, const std::vector<scan_files::RegisteredScan>& scans, const LearnSpec& spec,
                              LearnReport* report = nullptr, const LearnProgress& progress = {});

// The weakest start for bootstrapping: the model's template alone (its mean body with its skeleton,
// skinning, landmarks and anatomy) and no shape space, so the first round's registrations owe
// nothing to any population but the one template body.
format::ModelData template_only(const format::ModelData& model);

}  // namespace ssc::learning
