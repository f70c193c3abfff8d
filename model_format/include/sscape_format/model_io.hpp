// Reading and writing .sscape files.
#pragma once

#include "model_data.hpp"

#include <string>
#include <vector>

namespace ssc::format {

struct ReadOptions {
    uint64_t max_model_bytes = 0;          // 0 = kDefaultMaxModelBytes
    const Allocator* allocator = nullptr;  // for the model's arrays; null = C heap
};

// Decodes and fully verifies a file image. Throws ssc::Error; never returns a partial model.
ModelData read_model(const void* data, std::size_t size, const ReadOptions& options = {});

// Reads a whole file (SSC_ERROR_IO when it cannot) and decodes it; digest: NULL, or receives the
// content_digest (common/files.hpp) of the file's bytes.
ModelData read_model_file(const std::string& path, const ReadOptions& options = {}, std::string* digest = nullptr);

struct WriteOptions {
    int zstd_level = 19;
    // false: a 1.0 file (tree prediction only) that readers before container 2.0 read, about a
    // fifth larger for a symmetric body model.
    bool mirror_prediction = true;
    bool validate = true;  // false only for tests that must produce invalid files
};

// Validates (unless told not to) and encodes a model into a file image.
std::vector<unsigned char> write_model(const ModelData& m, const WriteOptions& options = {});

// Writes a file image atomically (temporary file + rename): no partial file on failure.
void write_file(const std::string& path, const std::vector<unsigned char>& bytes);

// Quantizes a float basis (scaled, metres per standard deviation; planar layout as QuantizedBasis)
// with the coarsest uniform step whose worst-case vertex error, every component at +-3 standard
// deviations, stays within tolerance (metres). Reports that error bound.
struct QuantizeReport {
    double max_error = 0;   // metres: bound on the largest vertex displacement caused
    double base_step = 0;   // metres per unit of the uniform step
};
QuantizedBasis quantize_basis(const float* basis, uint32_t vertex_count, uint32_t components, double tolerance,
                              QuantizeReport* report = nullptr);

// The error bound of a quantized basis against the float basis it came from (see quantize_basis).
double quantization_error_bound(const float* basis, const QuantizedBasis& qb, uint32_t vertex_count);

}  // namespace ssc::format
