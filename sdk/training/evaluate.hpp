// Statistical shape-model quality, as defined by Davies et al. and Styner et al.
// (compactness, generalization, specificity), measured for a range of component counts.
#pragma once

#include "pca.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::training {

struct QualityPoint {
    uint32_t components = 0;
    double compactness = 0;     // fraction of the training variance the first k components explain
    double generalization = 0;  // mean vertex distance (m) of held-out bodies to their k-component reconstruction
    double specificity = 0;     // mean vertex distance (m) of random k-component bodies to the nearest training body
};

// training: the (centred) training rows the PCA was computed from; heldout: bodies the PCA never
// saw (not centred). Specificity draws `samples` random bodies per k (coefficients ~ N(0, 1)).
std::vector<QualityPoint> evaluate_quality(const Pca& p, const SampleMatrix& training_centred, const SampleMatrix& heldout,
                                           const std::vector<uint32_t>& ks, uint32_t samples, uint32_t seed);

// Writes the table as CSV and three PNG plots next to it (prefix + "compactness.png" and so on,
// drawn by render/plot.hpp). Returns the PNG paths written.
std::vector<std::string> write_quality_report(const std::string& prefix, const std::vector<QualityPoint>& q);

}  // namespace ssc::training
