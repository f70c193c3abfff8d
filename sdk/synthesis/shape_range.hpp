// The shape coefficients the library accepts. Coefficients are in standard deviations of the
// training population; beyond a few the bodies stop looking human, and far beyond that they grow
// without bound (a coefficient of 1e9 makes a body 1e8 m tall). Everything that takes a shape from
// outside (the C API, the command line through it) refuses values outside +-kShapeLimit, naming the
// range; the fitter and bodies made to measure keep their solutions inside it.
#pragma once

#include "common/error.hpp"

#include <sscape/sscape.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>

namespace ssc {

inline constexpr float kShapeLimit = SSC_SHAPE_COEFFICIENT_LIMIT;

// A computed coefficient moved into [-kShapeLimit, kShapeLimit]: the box solvers keep to.
inline double within_shape_range(double c) { return std::clamp(c, -double(kShapeLimit), double(kShapeLimit)); }

// Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) naming the first coefficient that is not finite
// or lies outside [-kShapeLimit, kShapeLimit]; `what` names the array in the message.
inline void check_shape_coefficients(const float* c, std::size_t n, const char* what) {
    for (std::size_t i = 0; i < n; ++i) {
        if (std::isfinite(c[i]) && std::abs(c[i]) <= kShapeLimit) continue;
        char value[32];
        std::snprintf(value, sizeof value, "%g", double(c[i]));
        fail(SSC_ERROR_INVALID_ARGUMENT, std::string(what) + "[" + std::to_string(i) + "] is " + value +
                                             "; shape coefficients must be finite and within +-" +
                                             std::to_string(int(kShapeLimit)) + " standard deviations");
    }
}

}  // namespace ssc
