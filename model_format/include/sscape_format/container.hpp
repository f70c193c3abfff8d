// The .sscape container: a fixed 40-byte little-endian header followed by one zstd frame
// (content checksum on) holding the FlatBuffers model. Layout in model_format/README.md.
#pragma once

#include "common/alloc.hpp"

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
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

// The context's allocator for a buffer that is written whole right after it is sized: resize()
// leaves the bytes as they are. A model's decompressed content is 10 MB that a zero fill would write
// twice; in a browser's first, unoptimised WebAssembly tier the fill took about 150 ms of a page's load.
class ContentAlloc : public CAlloc<unsigned char> {
public:
    using CAlloc<unsigned char>::CAlloc;
    template <class U>
    struct rebind {
        static_assert(std::is_same_v<U, unsigned char>, "ContentAlloc holds bytes");
        using other = ContentAlloc;
    };
    void construct(unsigned char* p) noexcept { ::new (static_cast<void*>(p)) unsigned char; }
    void construct(unsigned char* p, unsigned char v) noexcept { *p = v; }
};
using ContentBuffer = std::vector<unsigned char, ContentAlloc>;

// Checks the header and the frame, then decompresses into out (sized exactly, allocated only after
// the sizes were checked against max_bytes). Throws MODEL_CORRUPT / UNSUPPORTED_VERSION.
void unpack_container(const void* data, std::size_t size, uint64_t max_bytes, ContentBuffer& out);

}  // namespace ssc::format
