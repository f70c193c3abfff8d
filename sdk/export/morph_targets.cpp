#include "export/morph_targets.hpp"

#include "common/error.hpp"

#include <cmath>

namespace ssc::exporters {

std::vector<MorphTarget> morph_targets(const Model& model, const semantics::AttributeModel& attributes, MorphKind kind, uint32_t count) {
    std::vector<MorphTarget> out;
    const uint32_t K = model.component_count();
    if (kind == MorphKind::Components) {
        SSC_REQUIRE_ARG_S(count >= 1 && count <= K, "morph targets: " << count << " components of a model with " << K);
        for (uint32_t k = 0; k < count; ++k) {
            MorphTarget m{"component_" + std::to_string(k + 1), "component", std::vector<float>(K, 0.f), 1.0, "sd"};
            m.coefficients[k] = 1.f;
            out.push_back(std::move(m));
        }
    } else if (kind == MorphKind::Sliders) {
        const std::vector<int>& sliders = attributes.sliders();
        SSC_REQUIRE_ARG(!sliders.empty(), "morph targets: the model has no semantic sliders");
        SSC_REQUIRE_ARG_S(count <= sliders.size(), "morph targets: " << count << " sliders of a model with " << sliders.size());
        const uint32_t S = count ? count : uint32_t(sliders.size());
        for (uint32_t s = 0; s < S; ++s) {
            const format::Attribute& a = attributes.attributes()[std::size_t(sliders[s])];
            const double sd = attributes.standard_deviation(sliders[s]);
            MorphTarget m{a.name, "slider", std::vector<float>(K), sd, a.unit};
            for (uint32_t k = 0; k < K; ++k) m.coefficients[k] = float(attributes.slider_directions()(k, s) * sd);
            out.push_back(std::move(m));
        }
    }
    return out;
}

}  // namespace ssc::exporters
