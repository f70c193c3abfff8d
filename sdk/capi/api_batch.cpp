// Batch synthesis on the context's worker threads.
#include "guard.hpp"
#include "handles.hpp"
#include "synthesis/shape_range.hpp"
#include "synthesis/batch.hpp"
#include "synthesis/rotation.hpp"

#include <cmath>
#include <cstring>
#include <vector>

using namespace ssc;
using namespace ssc::capi;

extern "C" {

void ssc_batch_desc_init(ssc_batch_desc* desc, size_t size) {
    if (!desc || size < sizeof(uint32_t)) return;
    ssc_batch_desc d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.pose_format = SSC_ROTATION_QUATERNION;
    std::memcpy(desc, &d, d.struct_size);
}

ssc_status ssc_model_synthesize_batch(const ssc_model* model, const ssc_batch_desc* desc) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(desc, "desc");
        const ssc_batch_desc d = read_def(desc, ssc_batch_desc_init, "desc");
        const Model& m = model->model;
        const uint32_t J = m.joint_count(), K = m.component_count();
        SSC_REQUIRE_ARG_S(d.level <= m.level_count(), "desc->level " << d.level << " is out of range (count " << m.level_count() + 1 << ", 0 the full mesh)");
        const uint32_t V = m.level_mesh(d.level).vertex_count;  // the level's vertices
        const std::size_t n = d.body_count;
        if (n == 0) return;
        SSC_REQUIRE_ARG(d.shape_count <= K, "shape_count is " + std::to_string(d.shape_count) + "; the model has " +
                                            std::to_string(K) + " components");
        const int32_t format = enum_value(d.pose_format);
        SSC_REQUIRE_ARG(format == SSC_ROTATION_QUATERNION || format == SSC_ROTATION_AXIS_ANGLE,
                        "desc->pose_format " + std::to_string(format) + " is not an ssc_rotation_format value");
        check_output(d.vertices, d.vertices_capacity, uint64_t(n) * V, 0, 12);
        if (d.normals) check_output(d.normals, d.normals_capacity, uint64_t(n) * V, 0, 12);
        if (d.shapes) {
            check_shape_coefficients(d.shapes, n * d.shape_count, "desc->shapes");
        } else {
            SSC_REQUIRE_ARG(d.shape_count == 0, "shape_count must be 0 when shapes is NULL");
        }
        if (d.translations)
            for (std::size_t i = 0; i < 3 * n; ++i)
                SSC_REQUIRE_ARG(std::isfinite(d.translations[i]), "translations[" + std::to_string(i) + "] is not finite");
        if (d.poses) {  // every pose checked before any body is made; converted on the workers
            const std::size_t width = d.pose_format == SSC_ROTATION_QUATERNION ? 4 : 3;
            for (std::size_t b = 0; b < n; ++b) {
                std::string error;
                if (!check_rotations(d.pose_format, d.poses + b * width * J, J, error))
                    fail(SSC_ERROR_INVALID_ARGUMENT, "body " + std::to_string(b) + ": " + error);
            }
        }
        BatchJob job;
        job.count = n;
        job.shapes = d.shapes;
        job.shape_count = d.shape_count;
        job.poses = d.poses;
        job.pose_format = d.pose_format;
        job.translations = d.translations;
        job.vertices = d.vertices;
        job.normals = d.normals;
        job.level = d.level;
        synthesize_batch(m, model->context->pool, job);
    });
}

}  // extern "C"
