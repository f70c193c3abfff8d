// How good a shape space learned from registrations is, by the measures of the reference paper
// (after Styner et al.): compactness (the share of the variance the first k components hold),
// generalization (how closely k components reconstruct registrations they were not learned from)
// and specificity (how close random bodies of k components come to a real registration).
// `sscape evaluate` draws them; docs/learning.md reports them.
#pragma once

#include "learning/learn_model.hpp"
#include "training/evaluate.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ssc::learning {

struct EvaluationSpec {
    std::vector<uint32_t> components;  // the k measured; empty: 1 to 10, then every 5th up to 50, within reach
    uint32_t folds = 0;                // 0: leave-one-out up to 100 registrations, 10 folds above
    uint32_t samples = 10000;          // random bodies per k for specificity
    uint32_t seed = 1;
};

using EvaluationProgress = std::function<void(const std::string& stage)>;

// Learning from the rows of `bodies` (normalized_bodies' output): compactness and specificity of
// the model learned from all of them; generalization by cross-validation, each fold's model
// reconstructing the bodies it was not learned from. Throws ssc::Error (INVALID_ARGUMENT) for
// fewer than 3 bodies or folds outside [2, bodies].
std::vector<training::QualityPoint> evaluate_learning(const training::SampleMatrix& bodies, const EvaluationSpec& spec,
                                                      const EvaluationProgress& progress = {});

// Learning from fewer registrations (the paper's 50, 100, 1,000, all): every fifth body is held out;
// each size n learns from n of the others (a seeded random order, so each set holds the smaller
// ones) and is measured by its own compactness, its generalization to the held-out bodies and its
// specificity against its own n bodies. sizes: 0 means all the others; sizes beyond them are
// left out. Throws ssc::Error (INVALID_ARGUMENT) for fewer than 10 bodies or a size below 3.
struct SizedQuality {
    uint32_t size = 0;
    std::vector<training::QualityPoint> points;
};
std::vector<SizedQuality> evaluate_training_sizes(const training::SampleMatrix& bodies, const std::vector<uint32_t>& sizes,
                                                  const EvaluationSpec& spec, const EvaluationProgress& progress = {});

// A given model (of the same template, in the template's frame, as learn_model writes them)
// measured against the bodies: generalization, each body reconstructed from k of the model's
// components after a rigid alignment onto its mean; specificity, the model's random bodies
// against the nearest of them; compactness, the share of the model's own stored variance (its file
// keeps only its components, so this is relative to what it kept, not to the bodies').
std::vector<training::QualityPoint> evaluate_model(const format::ModelData& model, const training::SampleMatrix& bodies,
                                                   const EvaluationSpec& spec);

}  // namespace ssc::learning
