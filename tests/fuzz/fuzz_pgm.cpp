// libFuzzer target: the reader of 16-bit PGM depth images with sscape camera comments, over bytes in memory. A malformed file must give
// ssc::Error with a status; anything else (a crash, a sanitizer report, another exception, a hang,
// unbounded memory) is a finding.
#include "common/error.hpp"
#include "io/readers.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        ssc::io::parse_pgm_depth(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    } catch (const ssc::Error& e) {
        if (e.status() == SSC_ERROR_INTERNAL) __builtin_trap();  // a broken postcondition, not bad input
    }
    return 0;
}
