// One segment's coefficients out of a fitted shape, whose layout is LinearModel's with segments
// (kinematics.hpp): the whole body's components, then every segment's in the model's order. The C
// API's fitter and registration hand them out the same way.
#pragma once

#include "common/error.hpp"
#include "synthesis/model.hpp"

#include <cstdint>
#include <vector>

namespace ssc::fitting {

// The segment's coefficients (SegmentSpace::components of them); zeros where the shape holds no
// segment components (a fit without them). Throws an argument error for a segment out of range.
inline std::vector<float> fitted_segment_shape(const Model& m, const std::vector<double>& shape, uint32_t segment) {
    SSC_REQUIRE_ARG_S(segment < m.segments().size(), "segment " << segment << " is out of range (the model has " << m.segments().size() << ")");
    const SegmentSpace& s = m.segments()[segment];
    std::vector<float> out(s.components, 0.f);
    for (uint32_t k = 0; k < s.components; ++k) {
        const std::size_t i = std::size_t(m.component_count()) + s.first + k;
        if (i < shape.size()) out[k] = float(shape[i]);
    }
    return out;
}

}  // namespace ssc::fitting
