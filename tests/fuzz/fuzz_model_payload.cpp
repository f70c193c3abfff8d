// libFuzzer target: the FlatBuffers payload of a model behind a valid container. The input is
// packed (correct header, sizes and checksums) before loading, so what the fuzzer exercises is
// the FlatBuffers verifier and the model's semantic validation, not the checksums.
#include "sscape_format/container.hpp"

#include <sscape/sscape.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_use_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::vector<unsigned char> file = ssc::format::pack_container(data, size, 1);
    ssc_model* model = nullptr;
    const ssc_status status = ssc_model_load_memory(nullptr, file.data(), file.size(), &model);
    if (status == SSC_ERROR_INTERNAL) __builtin_trap();  // a bug, not a bad file
    if (status != SSC_OK) return 0;
    fuzz::use_model(model);
    ssc_model_release(model);
    return 0;
}
