// libFuzzer target: a whole .sscape file from memory through the C API, as an application loads
// one it was sent. Most inputs die at the container checks (magic, sizes, XXH64, zstd); the
// payload target (fuzz_model_payload.cpp) reaches past them. What loads is then used: a body is
// made, shaped, posed and measured, so the semantic checks are held to what the runtime relies on.
#include <sscape/sscape.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_use_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    ssc_model* model = nullptr;
    const ssc_status status = ssc_model_load_memory(nullptr, data, size, &model);
    if (status == SSC_ERROR_INTERNAL) __builtin_trap();  // a bug, not a bad file
    if (status != SSC_OK) return 0;
    fuzz::use_model(model);
    ssc_model_release(model);
    return 0;
}
