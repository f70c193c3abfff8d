#include "synthesis/random_shapes.hpp"

#include <cmath>
#include <random>

namespace ssc {

std::vector<float> random_shapes(const Model& model, uint32_t seed, uint32_t count, float truncation) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> normal;
    std::vector<float> out(std::size_t(count) * model.component_count());
    for (float& c : out) do c = normal(rng); while (std::abs(c) > truncation);
    return out;
}

}  // namespace ssc
