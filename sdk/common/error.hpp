// Internal error type: thrown inside the library, turned into an ssc_status + message at the C
// boundary (capi/guard.hpp). Never crosses the ABI.
#pragma once

#include <sscape/sscape.h>

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

// For untrusted model data: a failed check names what was wrong.
inline void require_model(bool ok, const std::string& what) {
    if (!ok) fail(SSC_ERROR_MODEL_CORRUPT, what);
}

inline void require_arg(bool ok, const std::string& what) {
    if (!ok) fail(SSC_ERROR_INVALID_ARGUMENT, what);
}

}  // namespace ssc
