// The C boundary: every exported function runs its body through guarded(), so no C++ exception
// crosses the ABI and every failure leaves a status and a thread-local message.
#pragma once

#include "common/error.hpp"

#include <cstring>
#include <new>
#include <string>

namespace ssc::capi {

void set_last_error(const std::string& message);

template <class F>
ssc_status guarded(const char* function, F&& body) noexcept {
    try {
        body();
        return SSC_OK;
    } catch (const Error& e) {
        set_last_error(std::string(function) + ": " + e.what());
        return e.status();
    } catch (const std::bad_alloc&) {
        set_last_error(std::string(function) + ": out of memory");
        return SSC_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        set_last_error(std::string(function) + ": internal error: " + e.what());
        return SSC_ERROR_INTERNAL;
    } catch (...) {
        set_last_error(std::string(function) + ": internal error");
        return SSC_ERROR_INTERNAL;
    }
}

// Argument checks shared by the exported functions.
template <class T>
void need(const T* p, const char* name) {
    SSC_REQUIRE_ARG(p != nullptr, std::string(name) + " is NULL");
}

// The integer behind an enum argument from C. C callers may pass any int (-1, 42); loading such
// a value as the C++ enum type is undefined behaviour, so its bytes are read as an integer instead,
// before any range check.
template <class E>
int32_t enum_value(const E& e) {
    static_assert(sizeof(E) == sizeof(int32_t), "C API enums are 32-bit (their FORCE32 enumerator)");
    int32_t v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

// A def struct's optional string: NULL reads as empty.
inline std::string optional_string(const char* s) { return s ? std::string(s) : std::string(); }

// Checks an output array of count elements of elem_bytes at stride (0 = packed); returns the stride.
std::size_t check_output(const void* out, uint64_t capacity, uint64_t count, std::size_t stride, std::size_t elem_bytes);

// Copies n xyz triples (packed) to out at stride (at least 12 bytes).
inline void copy_xyz(const float* src, std::size_t n, float* out, std::size_t stride) {
    if (stride == 12) {
        std::memcpy(out, src, n * 12);
        return;
    }
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (std::size_t i = 0; i < n; ++i) std::memcpy(base + i * stride, src + 3 * i, 12);
}

// Reads a caller's def struct: defaults first, then the struct_size bytes the caller declared.
template <class Def>
Def read_def(const Def* def, void (*init)(Def*, std::size_t), const char* name) {
    Def out;
    init(&out, sizeof out);
    if (!def) return out;
    SSC_REQUIRE_ARG(def->struct_size >= sizeof(uint32_t) && def->struct_size <= sizeof(Def),
                std::string(name) + "->struct_size is " + std::to_string(def->struct_size) + "; expected " +
                    std::to_string(sizeof(Def)) + " (use the _def_init function)");
    std::memcpy(&out, def, def->struct_size);
    out.struct_size = sizeof(Def);
    return out;
}

}  // namespace ssc::capi
