// libFuzzer target for the fit parameters `sscape fit --params` writes and `synth` / `measure
// --params` read (cli::parse_params over the C API, the built-in model), over bytes in memory.
// A malformed file must give the command line's own errors (UsageError or the C API's failure as
// std::runtime_error, each a message and exit 1); anything else (a crash, a sanitizer report,
// another exception, a hang, unbounded memory) is a finding.
#include "cli/body_inputs.hpp"

#include <sscape/sscape.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    static ssc_model* model = [] {
        ssc_model* m = nullptr;
        if (ssc_model_load_default(nullptr, &m) != SSC_OK) __builtin_trap();
        return m;
    }();
    try {
        const ssc::cli::FitParams p = ssc::cli::parse_params(model, std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
        // What synth does with what was read: a body posed by it.
        ssc_body* body = nullptr;
        if (ssc_body_create(model, nullptr, &body) != SSC_OK) __builtin_trap();
        const ssc_status shaped = ssc_body_set_shape(body, p.shape.data(), uint32_t(p.shape.size()));
        const ssc_status posed = ssc_body_set_pose(body, p.pose.data(), ssc_model_joint_count(model), p.translation.data());
        ssc_body_destroy(body);
        if (shaped != SSC_OK || posed != SSC_OK) __builtin_trap();  // read as good, then refused: the reader's checks fall short
    } catch (const std::runtime_error&) {
        // UsageError derives from it: a clear message, the command's exit 1.
    }
    return 0;
}
