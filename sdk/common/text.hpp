// printf-style formatting into a std::string of whatever length the text needs: messages that hold
// names and paths are never cut (a fixed buffer cut a long path's line, and the words after it).
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace ssc {

#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline std::string format_text(const char* format, ...) {
    std::va_list args;
    va_start(args, format);
    std::va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(n > 0 ? std::size_t(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, again);
    va_end(again);
    return out;
}

}  // namespace ssc
