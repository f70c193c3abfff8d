// Container header (little-endian, 40 bytes):
//   0  magic[8]            89 53 53 43 41 50 45 0A  ("\x89SSCAPE\n": catches text-mode transfers)
//   8  u16 version_major    readers reject another major
//  10  u16 version_minor    newer minors only append schema fields: readers accept them
//  12  u32 flags            bit 0 = zstd payload (must be set); other bits reserved, must be 0
//  16  u64 payload_size     bytes of the zstd frame that follows; header + payload = file size
//  24  u64 content_size     bytes of the FlatBuffers buffer inside; equals the frame's content size
//  32  u64 checksum         XXH64 (seed 0) of bytes 0..31 followed by the payload
// zstd's own checksum covers only the decompressed content; ours also covers the header and
// the frame's header fields, so any damaged byte is detected before decompression.
#include "sscape_format/container.hpp"

#include "common/error.hpp"

// Frame-header inspection lives in zstd's experimental section; we link zstd statically.
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>
#define XXH_INLINE_ALL  // header-only use of Debian's xxhash
#include <xxhash.h>

#include <cstring>
#include <string>

namespace ssc::format {
namespace {

constexpr uint32_t kFlagZstd = 1u;

void put_u16(unsigned char* p, uint16_t v) {
    for (int i = 0; i < 2; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void put_u32(unsigned char* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void put_u64(unsigned char* p, uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
uint64_t checksum(const unsigned char* header, const unsigned char* payload, std::size_t payload_size) {
    XXH64_state_t state;
    XXH64_reset(&state, 0);
    XXH64_update(&state, header, 32);
    XXH64_update(&state, payload, payload_size);
    return XXH64_digest(&state);
}

uint64_t get_le(const unsigned char* p, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

}  // namespace

std::vector<unsigned char> pack_container(const void* payload, std::size_t size, int level, uint16_t major) {
    std::vector<unsigned char> out(kHeaderSize + ZSTD_compressBound(size));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    if (!cctx) throw std::bad_alloc();
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 1);
    const std::size_t n = ZSTD_compress2(cctx, out.data() + kHeaderSize, out.size() - kHeaderSize, payload, size);
    ZSTD_freeCCtx(cctx);
    if (ZSTD_isError(n)) fail(SSC_ERROR_INTERNAL, std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
    out.resize(kHeaderSize + n);
    std::memcpy(out.data(), kMagic, 8);
    put_u16(out.data() + 8, major);
    put_u16(out.data() + 10, kContainerMinor);
    put_u32(out.data() + 12, kFlagZstd);
    put_u64(out.data() + 16, n);
    put_u64(out.data() + 24, size);
    put_u64(out.data() + 32, checksum(out.data(), out.data() + kHeaderSize, n));
    return out;
}

void unpack_container(const void* data, std::size_t size, uint64_t max_bytes, ContentBuffer& out) {
    const auto* p = static_cast<const unsigned char*>(data);
    SSC_REQUIRE_MODEL(size >= kHeaderSize, "file is " + std::to_string(size) + " bytes, shorter than the " +
                                           std::to_string(kHeaderSize) + "-byte header");
    SSC_REQUIRE_MODEL(std::memcmp(p, kMagic, 8) == 0, "bad magic at offset 0: not a .sscape file");
    const auto major = static_cast<uint16_t>(get_le(p + 8, 2));
    const auto minor = static_cast<uint16_t>(get_le(p + 10, 2));
    if (major < kOldestContainerMajor || major > kContainerMajor)
        fail(SSC_ERROR_UNSUPPORTED_VERSION, "container version " + std::to_string(major) + "." +
                                                std::to_string(minor) + " (offset 8); this library reads " +
                                                std::to_string(kOldestContainerMajor) + ".x to " + std::to_string(kContainerMajor) + ".x");
    const auto flags = static_cast<uint32_t>(get_le(p + 12, 4));
    SSC_REQUIRE_MODEL(flags == kFlagZstd, "unknown container flags 0x" + std::to_string(flags) + " at offset 12");
    const uint64_t payload = get_le(p + 16, 8);
    const uint64_t content = get_le(p + 24, 8);
    SSC_REQUIRE_MODEL(payload == size - kHeaderSize, "payload size " + std::to_string(payload) +
                                                     " (offset 16) does not match the file: " +
                                                     std::to_string(size - kHeaderSize) + " bytes follow the header");
    SSC_REQUIRE_MODEL(content > 0 && content <= max_bytes,
                  "content size " + std::to_string(content) + " (offset 24) is outside 1.." + std::to_string(max_bytes));

    const unsigned char* frame = p + kHeaderSize;
    SSC_REQUIRE_MODEL(get_le(p + 32, 8) == checksum(p, frame, payload), "checksum (offset 32) does not match: the file is damaged");
    ZSTD_frameHeader fh;
    const std::size_t hr = ZSTD_getFrameHeader(&fh, frame, payload);
    SSC_REQUIRE_MODEL(hr == 0, "zstd frame header at offset " + std::to_string(kHeaderSize) + " is " + std::string(ZSTD_isError(hr) ? "invalid" : "truncated"));
    SSC_REQUIRE_MODEL(fh.frameType == ZSTD_frame, "the payload is a skippable frame, not a zstd frame");
    SSC_REQUIRE_MODEL(fh.frameContentSize == content, "zstd frame content size differs from the header's content size");
    SSC_REQUIRE_MODEL(fh.checksumFlag == 1, "zstd frame has no content checksum");
    const std::size_t csize = ZSTD_findFrameCompressedSize(frame, payload);
    SSC_REQUIRE_MODEL(!ZSTD_isError(csize), "zstd frame is truncated or invalid");
    SSC_REQUIRE_MODEL(csize == payload, "payload holds " + std::to_string(payload - csize) + " bytes after the zstd frame");

    out.resize(static_cast<std::size_t>(content));
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), frame, payload);
    if (ZSTD_isError(n)) {
        out.clear();
        fail(SSC_ERROR_MODEL_CORRUPT, std::string("zstd payload: ") + ZSTD_getErrorName(n));
    }
    SSC_REQUIRE_MODEL(n == content, "zstd payload decompressed to a different size than declared");
}

}  // namespace ssc::format
