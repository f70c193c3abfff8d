// Many bodies at once, spread over a thread pool. Bodies are processed in groups so the shape
// stage reads the basis once per group (see kernels_shape.cpp).
#pragma once

#include "common/thread_pool.hpp"
#include "model.hpp"

#include <sscape/sscape.h>

namespace ssc {

struct BatchJob {
    std::size_t count = 0;
    const float* shapes = nullptr;   // count * shape_count, or null
    uint32_t shape_count = 0;
    const float* poses = nullptr;    // count * J rotations of pose_format (checked: rotation.hpp), or null (rest pose)
    ssc_rotation_format pose_format = SSC_ROTATION_QUATERNION;
    const float* translations = nullptr;  // count * 3, or null
    float* vertices = nullptr;       // count * 3V
    float* normals = nullptr;        // count * 3V, or null
    uint32_t level = 0;              // 0 the full mesh; l > 0 the model's level l - 1 (V its vertices then)
};

// Inputs must be valid (checked by the caller).
void synthesize_batch(const Model& m, ThreadPool& pool, const BatchJob& job);

}  // namespace ssc
