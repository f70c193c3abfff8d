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

// An attribute that is not measured on the body but known per training body (sex, age, anything
// numeric a scan collection records): values[i] belongs to row i of the samples.
struct KnownAttribute {
    std::string name, unit, description;
    bool slider = true;
    std::vector<double> values;
};

// The MakeHuman population's own parameters as known attributes: sex, age, muscle, proportions.
std::vector<KnownAttribute> population_attributes(const std::vector<BodyParams>& people);

// `model` is complete but for its attributes; rows [0, fit) of X are the PCA's centred training
// bodies, `known` their attributes beyond the measurements. Measures every body's reconstruction
// in the model (so the statistics describe what the runtime measures), in parallel. The attributes
// are the measurements (but volume), then `known` in order.
format::AttributeModel learn_attribute_model(const format::ModelData& model, const SampleMatrix& X, const Pca& p, uint32_t fit,
                                             const std::vector<KnownAttribute>& known);

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
