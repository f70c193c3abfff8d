// The attribute model of a trained shape space (semantics/attribute_model.hpp): every training
// body's measurements and population parameters beside its shape coefficients, summarised as one
// Gaussian; and the held-out accuracy of bodies made to measure with it.
#pragma once

#include "pca.hpp"
#include "population.hpp"
#include "sscape_format/model_data.hpp"

#include <string>
#include <vector>

namespace ssc::training {

// `model` is complete but for its attributes; rows [0, fit) of X are the PCA's centred training
// bodies, people[i] their parameters. Measures every body's reconstruction in the model (so the
// statistics describe what the runtime measures), in parallel.
format::AttributeModel learn_attribute_model(const format::ModelData& model, const SampleMatrix& X, const Pca& p, uint32_t fit,
                                             const std::vector<BodyParams>& people);

// Made-to-measure accuracy on held-out bodies: each body's own mesh (not a model reconstruction)
// is measured, stature, chest, waist and hip girth are requested together with its sex and age,
// and the result is measured again.
struct MadeToMeasureAccuracy {
    std::vector<std::string> measurements;   // the requested ones
    std::vector<double> mean_error, worst_error;  // metres, per requested measurement
    std::vector<double> start_mean_error;    // the regression's start alone
    uint32_t bodies = 0, converged = 0;
    double mean_seconds = 0;
};

MadeToMeasureAccuracy evaluate_made_to_measure(const format::ModelData& model, const SampleMatrix& X, uint32_t first,
                                               uint32_t count, const std::vector<BodyParams>& people);

}  // namespace ssc::training
