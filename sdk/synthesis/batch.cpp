#include "batch.hpp"

#include "kernels.hpp"
#include "levels.hpp"
#include "rotation.hpp"

#include <algorithm>
#include <vector>

namespace ssc {

namespace {
constexpr std::size_t kGroup = 8;  // bodies sharing one pass over the basis
}

void synthesize_batch(const Model& m, ThreadPool& pool, const BatchJob& job) {
    const uint32_t V = m.vertex_count(), J = m.joint_count(), K = m.component_count();
    // A level of detail: the level's map of the rest body, posed by its own skin (as Body does).
    const format::DetailLevel* level = job.level ? &m.level(job.level - 1) : nullptr;
    const uint32_t N = level ? level->vertex_count : V;
    const std::size_t groups = (job.count + kGroup - 1) / kGroup;
    std::vector<float> identity(4ull * J, 0.f);
    for (uint32_t j = 0; j < J; ++j) identity[4 * j + 3] = 1.f;
    const std::size_t pose_width = job.pose_format == SSC_ROTATION_QUATERNION ? 4 : 3;

    // Scratch per thread, allocated before any output is written: an allocation failure leaves
    // the caller's buffers untouched.
    struct Scratch {
        std::vector<float> coeffs, rest, joints, skeleton, faces, posed, level_rest, quats;
        std::vector<kernels::SkinMatrix> skinning;
    };
    std::vector<Scratch> scratch(pool.size());
    for (auto& s : scratch) {
        s.coeffs.resize(kGroup * K);
        s.rest.resize(kGroup * m.padded_rows());
        s.joints.resize(kGroup * 3ull * J);
        s.skinning.resize(J);
        s.quats.resize(4ull * J);
        s.posed.resize(3ull * V);
        s.skeleton.resize(kernels::kSkeletonScratch * J);
        if (job.normals) s.faces.resize(3ull * (level ? level->triangle_count() : m.triangle_count()));
        if (level) s.level_rest.resize(3ull * N);
    }
    pool.parallel_for(groups, [&](std::size_t group, unsigned worker) {
        Scratch& s = scratch[worker];
        const std::size_t first = group * kGroup, n = std::min(kGroup, job.count - first);
        const float* cp[kGroup] = {};
        float* rp[kGroup] = {};
        float* jp[kGroup] = {};
        for (std::size_t g = 0; g < n; ++g) {
            float* c = &s.coeffs[g * K];
            std::fill(c, c + K, 0.f);
            if (job.shapes) std::copy_n(job.shapes + (first + g) * job.shape_count, job.shape_count, c);
            kernels::scale_coefficients(m, c, c);
            cp[g] = c;
            rp[g] = &s.rest[g * m.padded_rows()];
            jp[g] = &s.joints[g * 3ull * J];
        }
        kernels::shape(m, n, cp, rp, jp);
        const float zero[3] = {0, 0, 0};
        for (std::size_t g = 0; g < n; ++g) {
            const std::size_t b = first + g;
            // On the worker: the poses' sines and cosines are a few percent of a batch's time.
            const float* q = identity.data();
            if (job.poses) {
                std::string unused;  // checked before the batch began
                to_unit_quaternions(job.pose_format, job.poses + b * pose_width * J, J, s.quats.data(), unused);
                q = s.quats.data();
            }
            const float* t = job.translations ? job.translations + 3 * b : zero;
            kernels::skeleton(m, jp[g], q, t, s.skeleton.data(), nullptr, nullptr, s.skinning.data());
            if (level) {
                const SkinLayout& skin = m.level_skin(job.level - 1);
                levels::from_body(*level, rp[g], V, s.level_rest.data());
                kernels::skin_slots(skin, s.level_rest.data(), s.skinning.data(), s.posed.data(), 0, skin.slot_count(), kernels::active_isa());
            } else {
                kernels::skin(m, rp[g], s.skinning.data(), s.posed.data());
            }
            kernels::planar_to_xyz(s.posed.data(), N, job.vertices + b * 3ull * N, 12, /*streaming=*/true);
            if (job.normals && level)
                levels::normals(*level, m.level_topology(job.level - 1), s.posed.data(), s.faces.data(), job.normals + b * 3ull * N);
            else if (job.normals)
                kernels::normals(m, s.posed.data(), s.faces.data(), job.normals + b * 3ull * V);
        }
    });
}

}  // namespace ssc
