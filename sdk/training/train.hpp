// The training pipeline: MakeHuman assets -> population -> aligned bodies -> PCA -> skeleton,
// skin, vertex sets -> a model ready for the .sscape writer.
#pragma once

#include "attributes.hpp"
#include "detail_levels.hpp"
#include "evaluate.hpp"
#include "population.hpp"
#include "segment_shapes.hpp"
#include "sscape_format/model_data.hpp"
#include "sscape_format/model_io.hpp"

#include <functional>
#include <string>

namespace ssc::training {

struct TrainSpec {
    std::string assets_root;        // the shared/makehuman folder
    PopulationSpec population;
    uint32_t components = 50;
    uint32_t heldout = 200;         // bodies kept out of the joint regressor fit, for its error
    double tolerance = 1e-4;        // basis quantization bound, metres
    uint32_t regressor_support = 192; // body vertices per joint in the regressor (about)
    bool procrustes = false;        // rigid GPA; off for MakeHuman, whose bodies share one frame
    std::string population_csv;     // where to write the sampled parameters ("" = don't)
    std::string report_prefix;      // quality CSV and plots go to prefix + "quality.csv" etc. ("" = don't)
    uint32_t specificity_samples = 200;
    uint32_t made_to_measure_bodies = 200;  // held-out bodies the made-to-measure accuracy is measured on
    // Segment shape spaces (head, arms, torso, legs) over the same bodies: components per segment,
    // 0 for none; band: metres on each side of a segment border (see segment_layout).
    uint32_t segment_components = 0;
    double segment_band = 0.08;
    LevelSpec levels;               // levels of detail (none: no proxies and simplified_vertices 0)
};

struct TrainReport {
    uint32_t bodies = 0;
    double total_variance = 0;
    std::vector<double> stddev;                 // per component
    double regressor_mean_error = 0, regressor_max_error = 0;  // held-out, metres
    std::vector<std::pair<std::string, double>> joint_errors;  // held-out mean per joint, metres
    format::QuantizeReport quantization;
    std::vector<double> statures;               // per body, metres (after calibration)
    std::vector<int> male;                      // per body
    std::vector<QualityPoint> quality;          // compactness, generalization, specificity per k
    // Tape girths of every body (metres): chest at the bust points, waist at the iliac crest (the
    // NHANES protocol), natural waist (narrowest, at the CAESAR waist landmark), hip (largest
    // horizontal girth within 6 cm of the trochanters).
    std::vector<double> chest, waist_iliac, waist_natural, hip;
    std::vector<double> bmi;                    // per body: volume x density / stature^2
    std::vector<std::string> plots;             // PNG files written
    MadeToMeasureAccuracy made_to_measure;      // on held-out bodies
    std::vector<SegmentCompactness> segments;   // when learned: each segment's own components beside the whole body's
    std::vector<LevelReport> levels;            // the levels of detail made
};

// Called at the start of each stage (done = total = 0) and, within the long per-body stages, after
// each body; returning false cancels: train_model throws Error(SSC_ERROR_CANCELLED).
using Progress = std::function<bool(const std::string& stage, uint32_t done, uint32_t total)>;

format::ModelData train_model(const TrainSpec& spec, TrainReport& report, const Progress& progress = {});

}  // namespace ssc::training
