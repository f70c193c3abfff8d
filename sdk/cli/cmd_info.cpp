#include "cli.hpp"

#include <cstdio>
#include <fstream>

namespace ssc::cli {

int cmd_info(const std::vector<std::string>& args) {
    if (args.size() > 1) throw UsageError("info takes at most one MODEL");
    const std::string path = args.empty() ? "" : args[0];
    ssc_model* model = load_model(path);
    long long size = -1;
    if (!path.empty()) {
        std::ifstream f(path, std::ios::binary | std::ios::ate);
        size = static_cast<long long>(f.tellg());
    }

    auto meta = [&](ssc_metadata_key k) {
        const char* s = "";
        ssc_model_get_metadata(model, k, &s);
        return s;
    };
    if (path.empty()) std::printf("file:        (default model, built into the library)\n");
    else std::printf("file:        %s (%lld bytes, %.2f MB)\n", path.c_str(), size, size / 1e6);
    std::printf("name:        %s\n", meta(SSC_METADATA_NAME));
    std::printf("version:     %s\n", meta(SSC_METADATA_VERSION));
    std::printf("license:     %s\n", meta(SSC_METADATA_LICENSE));
    std::printf("units/axes:  %s, %s\n", meta(SSC_METADATA_UNITS), meta(SSC_METADATA_AXES));
    std::printf("provenance:  %s\n", meta(SSC_METADATA_PROVENANCE));
    std::printf("vertices:    %u\n", ssc_model_vertex_count(model));
    std::printf("triangles:   %u (quads %u, uvs %u)\n", ssc_model_triangle_count(model), ssc_model_quad_count(model),
                ssc_model_uv_count(model));
    std::printf("joints:      %u\n", ssc_model_joint_count(model));
    std::printf("landmarks:   %u\n", ssc_model_landmark_count(model));
    std::printf("vertex sets:");
    for (uint32_t i = 0; i < ssc_model_vertex_set_count(model); ++i) {
        const char* name = "";
        uint32_t n = 0;
        ssc_model_get_vertex_set(model, i, &name, &n);
        std::printf(" %s(%u)", name, n);
    }
    uint32_t limited = 0;
    for (uint32_t j = 0; j < ssc_model_joint_count(model); ++j) {
        ssc_joint_limit l{};
        check(ssc_model_get_joint_limit(model, j, &l), "joint limit");
        limited += l.limited;
    }
    std::printf("\njoint limits: %u joints\nsliders:     %u", limited, ssc_model_slider_count(model));
    for (uint32_t i = 0; i < ssc_model_slider_count(model); ++i) {
        ssc_slider_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_slider_info(model, i, &info), "slider");
        std::printf("\n  %-12s %-6s mean %8.3f, population %.3f .. %.3f", info.name, *info.unit ? info.unit : "-", info.mean,
                    info.minimum, info.maximum);
    }
    const uint32_t K = ssc_model_shape_count(model);
    std::printf("\ncomponents:  %u\nstddev (m):", K);
    std::vector<float> sd(K);
    if (K) check(ssc_model_get_shape_stddevs(model, sd.data(), K), "stddevs");
    for (uint32_t k = 0; k < K; ++k) std::printf("%s%.4g", k % 10 == 0 ? "\n  " : " ", sd[k]);
    std::printf("\n");
    ssc_model_release(model);
    return 0;
}

}  // namespace ssc::cli
