#include "model.hpp"

#include "kernels.hpp"

namespace ssc {

Model::Model(format::ModelData data, const Allocator* alloc)
    : data_(std::move(data)),
      V_(data_.vertex_count()),
      K_(data_.component_count()),
      J_(data_.joint_count()),
      mean_planar_(CAlloc<float>(alloc)),
      joint_mean_(CAlloc<float>(alloc)),
      joint_basis_(CAlloc<float>(alloc)),
      landmark_rest_(CAlloc<float>(alloc)) {
    mean_planar_.resize(3ull * V_);
    for (uint32_t v = 0; v < V_; ++v)
        for (int a = 0; a < 3; ++a) mean_planar_[a * V_ + v] = data_.shape.mean[3 * v + a];

    // Joints are linear in the vertices, so regressing the mean and each basis vector once lets a
    // body get its joints from the coefficients alone (J x K instead of touching the vertices).
    const auto& sk = data_.skeleton;
    joint_mean_.assign(3ull * J_, 0.f);
    joint_basis_.assign(3ull * J_ * K_, 0.f);
    const std::size_t rows = 3ull * V_;
    for (uint32_t j = 0; j < J_; ++j) {
        for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e) {
            const uint32_t v = sk.regressor_vertices[e];
            const float w = sk.regressor_weights[e];
            for (int a = 0; a < 3; ++a) {
                joint_mean_[3 * j + a] += w * mean_planar_[a * V_ + v];
                for (uint32_t k = 0; k < K_; ++k)
                    joint_basis_[(std::size_t(k) * J_ + j) * 3 + a] +=
                        w * data_.shape.basis.step[k] * float(data_.shape.basis.q[k * rows + a * V_ + v]);
            }
        }
    }

    for (uint32_t j = 0; j < J_; ++j) joint_index_.emplace(sk.joint_names[j], j);
    for (uint32_t l = 0; l < data_.landmarks.size(); ++l) landmark_index_.emplace(data_.landmarks[l].name, l);
    landmark_rest_.resize(3 * data_.landmarks.size());
    std::vector<float> xyz(rows);
    for (uint32_t v = 0; v < V_; ++v)
        for (int a = 0; a < 3; ++a) xyz[3 * v + a] = mean_planar_[a * V_ + v];
    kernels::landmarks(data_, xyz.data(), landmark_rest_.data(), 12);
}

int64_t Model::find_joint(const std::string& name) const {
    auto it = joint_index_.find(name);
    return it == joint_index_.end() ? int64_t{-1} : int64_t{it->second};
}

int64_t Model::find_landmark(const std::string& name) const {
    auto it = landmark_index_.find(name);
    return it == landmark_index_.end() ? int64_t{-1} : int64_t{it->second};
}

}  // namespace ssc
