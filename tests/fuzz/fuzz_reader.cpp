// libFuzzer target for one measurement file reader over bytes in memory, chosen when compiled:
// SSC_FUZZ_READER is parse_ply (ASCII, binary little and big endian), parse_obj, parse_lnd or
// parse_pgm_depth (tests/fuzz/CMakeLists.txt builds one target each). A malformed file must give
// ssc::Error with a status; anything else (a crash, a sanitizer report, another exception, a hang,
// unbounded memory, SSC_ERROR_INTERNAL) is a finding.
#include "common/error.hpp"
#include "io/readers.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        ssc::io::SSC_FUZZ_READER(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    } catch (const ssc::Error& e) {
        if (e.status() == SSC_ERROR_INTERNAL) __builtin_trap();  // a broken postcondition, not bad input
    }
    return 0;
}
