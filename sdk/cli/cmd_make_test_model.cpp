#include "cli.hpp"

#include "sscape_format/model_io.hpp"
#include "testing/synthetic_model.hpp"

#include <cstdio>

namespace ssc::cli {

int cmd_make_test_model(const std::vector<std::string>& args) {
    testing::SyntheticSpec spec;
    std::string out;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& { return option_value(args, i); };
        if (a == "-o" || a == "--output") out = value();
        else if (a == "--vertices") spec.vertex_count = parse_count(value(), a);
        else if (a == "--components") spec.components = parse_count(value(), a);
        else if (a == "--seed") spec.seed = parse_count(value(), a);
        else if (a == "--skeleton") {
            const std::string s = value();
            if (s == "humanoid") spec.skeleton = testing::SyntheticSkeleton::Humanoid53;
            else if (s == "mini") spec.skeleton = testing::SyntheticSkeleton::Mini6;
            else throw UsageError("--skeleton must be humanoid or mini");
        } else throw UsageError("unknown option '" + a + "'");
    }
    if (out.empty()) throw UsageError("make-test-model needs -o OUT.sscape");
    if (spec.components < 1 || spec.components > 1000) throw UsageError("--components must be 1..1000");
    if (spec.vertex_count > 2000000) throw UsageError("--vertices is limited to 2,000,000");
    const testing::SyntheticModel m = testing::build_synthetic_model(spec);
    const std::vector<unsigned char> bytes = format::write_model(m.data);
    format::write_file(out, bytes);
    std::printf("wrote %s: %zu bytes (%.3f MB), %u vertices, %u joints, %u components\n", out.c_str(), bytes.size(),
                bytes.size() / 1e6, m.data.vertex_count(), m.data.joint_count(), m.data.component_count());
    std::printf("basis quantization: worst vertex error %.4f mm with every component at +-3 SD (step %.3g um)\n",
                m.quantization.max_error * 1e3, m.quantization.base_step * 1e6);
    return 0;
}

}  // namespace ssc::cli
