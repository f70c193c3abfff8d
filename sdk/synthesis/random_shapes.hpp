// Random plausible shapes of a model, for `sscape synth --random`, `sscape measure --random` and
// ssc_model_sample_shapes: every coefficient standard normal, drawn again while beyond the
// truncation, so no body is implausibly extreme. One sequence per seed (std::mt19937), the same on
// every platform's libstdc++.
#pragma once

#include "synthesis/model.hpp"

#include <cstdint>
#include <vector>

namespace ssc {

// count shapes of model.component_count() coefficients each, one after another. truncation in
// standard deviations, > 0.
std::vector<float> random_shapes(const Model& model, uint32_t seed, uint32_t count, float truncation);

}  // namespace ssc
