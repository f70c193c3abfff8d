// Whole files in and out, for every reader and writer of the library and its tools.
//
// Reading opens regular files only: a directory, a FIFO or a device is refused before anything is
// read (a FIFO would block, a directory reports a nonsense size). Writing never shows a reader a
// partial file and never follows a planted link: the bytes go to an unnamed temporary file in the
// target's folder (O_TMPFILE), which gets a unique name only once complete and is then renamed over
// the target. A process killed while writing leaves nothing behind. Where the file system has no
// O_TMPFILE, a uniquely named temporary created with O_EXCL | O_NOFOLLOW is used instead.
#pragma once

#include "common/error.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace ssc {

// The whole content of the regular file at `path`. Throws ssc::Error: SSC_ERROR_IO when it cannot
// be opened or read or is not a regular file; `too_large` (with a message giving the size) when it
// holds more than max_bytes.
std::string read_regular_file(const std::string& path, uint64_t max_bytes, ssc_status too_large = SSC_ERROR_IO);

// Replaces (or creates) the file at `path` with `size` bytes, atomically, with the permissions a new
// file gets (0666 less the umask). Throws ssc::Error(SSC_ERROR_IO) and leaves the target unchanged
// on failure.
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

// A short digest of bytes (XXH3, 16 hex digits): which model file or scan a result was made from.
std::string content_digest(const void* data, std::size_t size);

}  // namespace ssc
