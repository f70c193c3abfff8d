// Bodies made to measure: shape coefficients that reproduce requested measurements.
//
// The start is the attribute model's regression: the population's conditional mean of the shape
// given the requested measurements and whatever else is known (sex, age). Levenberg-Marquardt on
// the real measurement functions (measure/measurements.hpp) then refines it: residuals are the
// differences to the request in units of 1 mm (0.1 kg, 10 cm2, 0.1 L), plus a weak pull towards
// the start that fixes the directions the request leaves free. The measurements are piecewise
// smooth functions of the vertices (tape hulls and searched levels), so their Jacobian is taken by
// forward differences over the shape coefficients.
#pragma once

#include "measure/measurements.hpp"
#include "semantics/attribute_model.hpp"
#include "synthesis/model.hpp"

#include <utility>
#include <vector>

namespace ssc::semantics {

struct MeasureTarget {
    int measurement = 0;  // measure::definitions() index
    double value = 0;     // SI units
};

struct MadeToMeasureOptions {
    std::vector<std::pair<int, double>> known;  // other attribute values (attribute index, value): sex, age
    int max_iterations = 15;
    double tolerance = 0.0005;  // metres: done when every requested length is this close (mass 50 g, ...)
};

struct MadeToMeasureResult {
    std::vector<float> coefficients;  // K
    std::vector<double> achieved;     // every measurement of the result, definitions() order
    std::vector<double> start;        // every measurement of the regression's start
    int iterations = 0;
    bool converged = false;           // every requested measurement within the tolerance
};

// Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) for an empty request, a measurement index out of
// range or requested twice, or a value that is not finite and positive.
MadeToMeasureResult make_to_measure(const Model& model, const measure::Measurer& measurer, const AttributeModel& attributes,
                                    const std::vector<MeasureTarget>& targets, const MadeToMeasureOptions& options = {});

}  // namespace ssc::semantics
