// Sampling a synthetic adult population from the MakeHuman sliders. Stature is drawn from survey
// statistics and reached by calibrating the height slider per body (the slider is not in
// centimetres). The population is stored as its parameters (CSV); meshes are regenerated from them.
#pragma once

#include "measure/measurements.hpp"
#include "makehuman/assets.hpp"

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace ssc::training {

struct PopulationSpec {
    uint32_t count = 4000;
    uint32_t seed = 1;
    double min_age = 18, max_age = 80;  // years, uniform
    double modifier_sd = 0.2;           // standard deviation of two-sided body-shape sliders
};

// Survey figures the sampler draws stature (metres) and body-mass index (kg/m^2, log-normal) from.
struct StatureStats {
    double male_mean = 1.754, male_sd = 0.075;
    double female_mean = 1.617, female_sd = 0.070;
    double male_bmi_mean = 29.1, male_bmi_sd = 6.0;
    double female_bmi_mean = 29.6, female_bmi_sd = 7.5;
};

// Whole-body density for mass from volume: the measurement stage's (sscape measure reports mass with it).
using measure::kBodyDensity;

struct BodyParams {
    bool male = false;
    double age_years = 0;
    mh::MacroSliders macro;
    std::vector<double> modifiers;  // one per Assets::modifiers
    double target_stature = 0;      // metres
    double target_bmi = 0;          // kg/m^2
};

// Called before each body with how many are done; returning false stops the sampling with
// Error(SSC_ERROR_CANCELLED). Calibrating each body's stature and weight takes most of a second.
using SamplingProgress = std::function<bool(uint32_t done, uint32_t total)>;

std::vector<BodyParams> sample_population(const mh::Assets& a, const PopulationSpec& spec, const StatureStats& stats = {},
                                          const SamplingProgress& progress = {});

// A body the model trained on the first `trained` modifiers cannot represent exactly: the person
// with the modifiers added after them (mh::add_modifier_groups) set at random over half their range
// (the ends are caricatures), none that move a part bodily (hand-trans, neck-trans: placement, not
// shape). Its rest vertices, x y z per vertex.
std::vector<float> beyond_model_body(const mh::Assets& a, const BodyParams& person, std::size_t trained, std::mt19937& rng);

// Stature (highest minus lowest body vertex, rest posture) of a generated body.
double stature(const std::vector<float>& xyz);

// Volume (m^3) enclosed by the body surface of a generated body (divergence theorem).
double body_volume(const mh::Assets& a, const std::vector<float>& xyz);

// Writes/reads the population as CSV: one row per body, a header naming every column.
void write_population_csv(const std::string& path, const mh::Assets& a, const std::vector<BodyParams>& bodies);

}  // namespace ssc::training
