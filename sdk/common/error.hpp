// Internal error type: thrown inside the library, turned into an ssc_status + message at the C
// boundary (capi/guard.hpp). Never crosses the ABI.
#pragma once

#include <sscape/sscape.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace ssc {

class Error : public std::runtime_error {
public:
    Error(ssc_status status, const std::string& message) : std::runtime_error(message), status_(status) {}
    ssc_status status() const noexcept { return status_; }

private:
    ssc_status status_;
};

[[noreturn]] inline void fail(ssc_status status, const std::string& message) { throw Error(status, message); }

}  // namespace ssc

// Checks whose message names what was wrong. Macros so that the message is built only on failure:
// many of these run once per vertex of untrusted model data.
#define SSC_REQUIRE_MODEL(ok, message)                                            \
    do {                                                                          \
        if (!(ok)) ::ssc::fail(SSC_ERROR_MODEL_CORRUPT, (message));               \
    } while (0)
#define SSC_REQUIRE_ARG(ok, message)                                              \
    do {                                                                          \
        if (!(ok)) ::ssc::fail(SSC_ERROR_INVALID_ARGUMENT, (message));            \
    } while (0)

// The same with a message streamed from parts: SSC_REQUIRE_ARG_S(n > 0, "got " << n << " points").
#define SSC_REQUIRE_ARG_S(ok, parts)                                              \
    do {                                                                          \
        if (!(ok)) {                                                              \
            std::ostringstream ssc_message_;                                      \
            ssc_message_ << parts;                                                \
            ::ssc::fail(SSC_ERROR_INVALID_ARGUMENT, ssc_message_.str());          \
        }                                                                         \
    } while (0)
