// The .sscape container: a fixed 40-byte little-endian header followed by one zstd frame
// (content checksum on) holding the FlatBuffers model. Layout in model_format/README.md.
#pragma once

#include "common/alloc.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssc::format {

inline constexpr unsigned char kMagic[8] = {0x89, 'S', 'S', 'C', 'A', 'P', 'E', 0x0A};
// 2.0 added the basis's mirror prediction, which a 1.x reader would decode wrongly: it refuses 2.x.
// This library reads 1.x and 2.x and writes 2.0.
inline constexpr uint16_t kContainerMajor = 2;
inline constexpr uint16_t kOldestContainerMajor = 1;
inline constexpr uint16_t kContainerMinor = 0;
inline constexpr std::size_t kHeaderSize = 40;
inline constexpr uint64_t kDefaultMaxModelBytes = 256ull << 20;

// Wraps a FlatBuffers payload into a container. level: zstd compression level; major: the version
// the payload needs (1 without mirror prediction).
std::vector<unsigned char> pack_container(const void* payload, std::size_t size, int level, uint16_t major = kContainerMajor);

// Checks the header and the frame, then decompresses into out (sized exactly, allocated only after
// the sizes were checked against max_bytes). Throws MODEL_CORRUPT / UNSUPPORTED_VERSION.
void unpack_container(const void* data, std::size_t size, uint64_t max_bytes, Vec<unsigned char>& out);

}  // namespace ssc::format
