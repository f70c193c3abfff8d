// Shape morph targets for engines: directions in the shape space that a GLB carries as morph
// targets, so an engine varies a body without the library (export/body_export.hpp writes them).
#pragma once

#include "semantics/attribute_model.hpp"
#include "synthesis/model.hpp"

#include <string>
#include <vector>

namespace ssc::exporters {

enum class MorphKind { None, Components, Sliders };

struct MorphTarget {
    std::string name;                 // "component_1", ... or the slider's attribute name
    std::string kind;                 // "component" or "slider"
    std::vector<float> coefficients;  // K: the whole-body shape change at weight 1
    double per_weight = 1;            // what weight 1 adds: 1 SD of the component, or of the slider's attribute
    std::string unit;                 // "sd" for a component; the attribute's unit ("m", "kg", "" for a ratio)
};

// Components: the first count shape components, weight 1 = +1 standard deviation. Sliders: every
// semantic slider (count 0) or the first count, weight 1 = +1 population standard deviation of the
// slider's attribute with the other sliders held. Throws SSC_ERROR_INVALID_ARGUMENT for more than
// the model has, and for sliders on a model without them.
std::vector<MorphTarget> morph_targets(const Model& model, const semantics::AttributeModel& attributes, MorphKind kind, uint32_t count);

}  // namespace ssc::exporters
