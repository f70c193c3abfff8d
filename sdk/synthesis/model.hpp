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

    const float* mean_planar() const { return mean_planar_.data(); }           // [axis][v]
    const int16_t* basis_q() const { return data_.shape.basis.q.data(); }       // [k][axis][v]
    const float* basis_step() const { return data_.shape.basis.step.data(); }   // [k]
    const float* joint_mean() const { return joint_mean_.data(); }             // [j][axis]
    const float* joint_basis() const { return joint_basis_.data(); }           // [k][j][axis], metres per SD
    const float* landmark_rest() const { return landmark_rest_.data(); }       // mean shape, [l][axis]

    // -1 when absent.
    int64_t find_joint(const std::string& name) const;
    int64_t find_landmark(const std::string& name) const;

private:
    format::ModelData data_;
    uint32_t V_, K_, J_;
    Vec<float> mean_planar_, joint_mean_, joint_basis_, landmark_rest_;
    std::unordered_map<std::string, uint32_t> joint_index_, landmark_index_;
};

}  // namespace ssc
