#include "cli.hpp"

#include "sscape_format/model_io.hpp"
#include "testing/synthetic_model.hpp"

#include <cstdio>

namespace ssc::cli {

namespace {

int run_make_test_model(const testing::SyntheticSpec& spec, const std::string& out) {
    const testing::SyntheticModel m = testing::build_synthetic_model(spec);
    const std::vector<unsigned char> bytes = format::write_model(m.data);
    format::write_file(out, bytes);
    std::printf("wrote %s: %zu bytes (%.3f MB), %u vertices, %u joints, %u components\n", out.c_str(), bytes.size(),
                bytes.size() / 1e6, m.data.vertex_count(), m.data.joint_count(), m.data.component_count());
    std::printf("basis quantization: worst vertex error %.4f mm with every component at +-3 SD (step %.3g um)\n",
                m.quantization.max_error * 1e3, m.quantization.base_step * 1e6);
    return 0;
}

}  // namespace

Run add_make_test_model(CLI::App& app) {
    struct Options {
        testing::SyntheticSpec spec;
        std::string out;
    };
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("make-test-model", "write a procedural test model (a smooth body-like mesh; for tests and benchmarks)");
    c->add_option("-o,--output", o->out, "the model file to write")->required()->type_name("OUT.sscape");
    c->add_option("--vertices", o->spec.vertex_count, "vertices of the mesh")->check(CLI::Range(16u, 2000000u))->capture_default_str();
    c->add_option("--components", o->spec.components, "shape components")->check(CLI::Range(1u, 1000u))->capture_default_str();
    c->add_option("--skeleton", o->spec.skeleton, "humanoid: the default model's 53 joints; mini: 6 joints")
        ->transform(CLI::CheckedTransformer(std::map<std::string, testing::SyntheticSkeleton>{
            {"humanoid", testing::SyntheticSkeleton::Humanoid53}, {"mini", testing::SyntheticSkeleton::Mini6}}).description(""))
        ->type_name("humanoid|mini")
        ->default_str("humanoid");
    c->add_option("--seed", o->spec.seed, "random seed")->capture_default_str();
    return [o] { return run_make_test_model(o->spec, o->out); };
}

}  // namespace ssc::cli
