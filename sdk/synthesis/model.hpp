// The runtime model: the decoded file plus what synthesis derives from it once at load
// (planar mean, joint regressor applied to the mean and the basis, name lookups). Immutable after
// construction and shared by every body; reference counted by the C API shim.
#pragma once

#include "common/alloc.hpp"
#include "sscape_format/model_data.hpp"

#include <string>
#include <unordered_map>

namespace ssc {

class Model {
public:
    // Takes the validated file contents. alloc must outlive the model.
    Model(format::ModelData data, const Allocator* alloc);

    const format::ModelData& data() const { return data_; }
    uint32_t vertex_count() const { return V_; }
    uint32_t component_count() const { return K_; }
    uint32_t joint_count() const { return J_; }
    uint32_t triangle_count() const { return static_cast<uint32_t>(data_.mesh.triangles.size() / 3); }

    // Synthesis works on "rows": the 3V coordinates in planar order (x block, y block, z block),
    // padded with zeros to a multiple of 16 (kChunk) so SIMD kernels never need a tail.
    static constexpr uint32_t kChunk = 16;
    std::size_t padded_rows() const { return padded_rows_; }
    const float* mean_planar() const { return mean_planar_.data(); }           // [row], padded
    // The basis in panel layout: for each chunk of 16 rows, all K components' 16 values in a row
    // ([chunk][k][16]), so a pass over the basis is one sequential stream.
    const int16_t* basis_panels() const { return basis_panels_.data(); }
    const float* basis_step() const { return data_.shape.basis.step.data(); }   // [k]
    const float* joint_mean() const { return joint_mean_.data(); }             // [j][axis]
    const float* joint_basis() const { return joint_basis_.data(); }           // [k][j][axis], per quantization unit
    const float* landmark_rest() const { return landmark_rest_.data(); }       // mean shape, [l][axis]

    // Skin influences grouped by count (1..4) so skinning runs branch-free loops that do only the
    // work each vertex needs. Group n: vertices, then n matrix offsets (in floats) and n weights each.
    struct SkinGroup {
        Vec<uint32_t> vertices;
        Vec<uint32_t> offsets;  // joint * 16
        Vec<float> weights;
    };
    const SkinGroup& skin_group(int influences) const { return skin_groups_[influences - 1]; }

    // Triangles around each vertex (CSR): normals gather face normals per vertex instead of
    // scattering into shared vertices, which stalls on store forwarding.
    const uint32_t* vertex_triangle_offsets() const { return vt_offsets_.data(); }  // V + 1
    const uint32_t* vertex_triangles() const { return vt_triangles_.data(); }

    // -1 when absent.
    int64_t find_joint(const std::string& name) const;
    int64_t find_landmark(const std::string& name) const;

private:
    format::ModelData data_;
    uint32_t V_, K_, J_;
    std::size_t padded_rows_;
    Vec<int16_t> basis_panels_;
    Vec<float> mean_planar_, joint_mean_, joint_basis_, landmark_rest_;
    SkinGroup skin_groups_[4];
    Vec<uint32_t> vt_offsets_, vt_triangles_;
    std::unordered_map<std::string, uint32_t> joint_index_, landmark_index_;
};

}  // namespace ssc
