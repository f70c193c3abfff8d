// Writing a whole file so that readers never see a partial one: write a temporary file beside
// it, then rename over the target. On failure the temporary is removed and nothing else changes.
#pragma once

#include "common/error.hpp"

#include <cstddef>
#include <cstdio>
#include <fstream>
#include <string>

namespace ssc {

inline void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) fail(SSC_ERROR_IO, "cannot open '" + tmp + "' for writing");
        f.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
        f.close();
        if (!f) {
            std::remove(tmp.c_str());
            fail(SSC_ERROR_IO, "cannot write '" + tmp + "'");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        fail(SSC_ERROR_IO, "cannot rename '" + tmp + "' to '" + path + "'");
    }
}

}  // namespace ssc
