#include "model.hpp"

#include "kernels.hpp"

#include <algorithm>

namespace ssc {

Model::Model(format::ModelData data, const Allocator* alloc)
    : data_(std::move(data)),
      V_(data_.vertex_count()),
      K_(data_.component_count()),
      J_(data_.joint_count()),
      padded_rows_((3ull * V_ + kChunk - 1) / kChunk * kChunk),
      basis_panels_(CAlloc<int16_t>(alloc)),
      mean_planar_(CAlloc<float>(alloc)),
      joint_mean_(CAlloc<float>(alloc)),
      joint_basis_(CAlloc<float>(alloc)),
      landmark_rest_(CAlloc<float>(alloc)) {
    mean_planar_.assign(padded_rows_, 0.f);
    for (uint32_t v = 0; v < V_; ++v)
        for (int a = 0; a < 3; ++a) mean_planar_[a * V_ + v] = data_.shape.mean[3 * v + a];
    const std::size_t rows = 3ull * V_;
    basis_panels_.assign(padded_rows_ * K_, 0);
    // Written in panel order (sequential stores, 16-value reads per component).
    int16_t* out = basis_panels_.data();
    for (std::size_t r0 = 0; r0 < padded_rows_; r0 += kChunk)
        for (uint32_t k = 0; k < K_; ++k, out += kChunk) {
            const int16_t* in = data_.shape.basis.q.data() + k * rows;
            for (std::size_t i = 0; i < kChunk && r0 + i < rows; ++i) out[i] = in[r0 + i];
        }

    // Joints are linear in the vertices, so regressing the mean and each basis vector once lets a
    // body get its joints from the coefficients alone (J x K instead of touching the vertices).
    // Like the vertex basis, the joint basis is per quantization unit (scaled by step at use).
    const auto& sk = data_.skeleton;
    joint_mean_.assign(3ull * J_, 0.f);
    joint_basis_.assign(3ull * J_ * K_, 0.f);
    for (uint32_t j = 0; j < J_; ++j) {
        for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e) {
            const uint32_t v = sk.regressor_vertices[e];
            const float w = sk.regressor_weights[e];
            for (int a = 0; a < 3; ++a) {
                const std::size_t r = std::size_t(a) * V_ + v;
                joint_mean_[3 * j + a] += w * mean_planar_[r];
                // The row's K values sit 16 apart in the panel layout: one cache-friendly sweep.
                const int16_t* q = basis_panels_.data() + (r / kChunk) * K_ * kChunk + r % kChunk;
                for (uint32_t k = 0; k < K_; ++k) joint_basis_[(std::size_t(k) * J_ + j) * 3 + a] += w * float(q[k * kChunk]);
            }
        }
    }

    skin_layout_ = build_skin_layout(V_, data_.skin.joints.data(), data_.skin.weights.data(), alloc);
    skin_blocks_ = build_skin_blocks(V_, data_.skin.joints.data(), data_.skin.weights.data(), alloc);

    const auto& tris = data_.mesh.triangles;
    vt_offsets_ = Vec<uint32_t>(V_ + 1, 0u, CAlloc<uint32_t>(alloc));
    vt_triangles_ = Vec<uint32_t>(tris.size(), 0u, CAlloc<uint32_t>(alloc));
    for (uint32_t i : tris) ++vt_offsets_[i + 1];
    for (uint32_t v = 0; v < V_; ++v) vt_offsets_[v + 1] += vt_offsets_[v];
    {
        std::vector<uint32_t> fill(vt_offsets_.begin(), vt_offsets_.end() - 1);
        for (std::size_t c = 0; c < tris.size(); ++c) vt_triangles_[fill[tris[c]]++] = static_cast<uint32_t>(c / 3);
    }

    segments_ = build_segment_spaces(data_, alloc);
    for (const auto& sg : segments_) segment_coefficients_ += sg.components;
    for (const auto& level : data_.levels) {
        level_topology_.emplace_back(level);
        level_skin_.push_back(build_skin_layout(level.vertex_count, level.skin_joints.data(), level.skin_weights.data(), alloc));
    }

    for (uint32_t j = 0; j < J_; ++j) joint_index_.emplace(sk.joint_names[j], j);
    for (uint32_t l = 0; l < data_.landmarks.size(); ++l) landmark_index_.emplace(data_.landmarks[l].name, l);
    landmark_rest_.resize(3 * data_.landmarks.size());
    kernels::landmarks(data_, mean_planar_.data(), landmark_rest_.data(), 12);
}

Model::LevelMesh Model::level_mesh(uint32_t level) const {
    if (level == 0) {
        const auto& mesh = data_.mesh;
        const bool uv = !mesh.uvs.empty();
        return {"full", V_, triangle_count(), uint32_t(mesh.uvs.size() / 2), mesh.triangles.data(), uv ? mesh.uvs.data() : nullptr,
                uv ? mesh.triangle_uvs.data() : nullptr, data_.skin.joints.data(), data_.skin.weights.data()};
    }
    const format::DetailLevel& l = data_.levels[level - 1];
    const bool uv = !l.uvs.empty();
    return {l.name.c_str(), l.vertex_count, l.triangle_count(), uint32_t(l.uvs.size() / 2), l.triangles.data(), uv ? l.uvs.data() : nullptr,
            uv ? l.triangle_uvs.data() : nullptr, l.skin_joints.data(), l.skin_weights.data()};
}

int64_t Model::find_joint(const std::string& name) const {
    auto it = joint_index_.find(name);
    return it == joint_index_.end() ? int64_t{-1} : int64_t{it->second};
}

int64_t Model::find_segment(const std::string& name) const {
    for (std::size_t s = 0; s < segments_.size(); ++s)
        if (segments_[s].name == name) return int64_t(s);
    return -1;
}

int64_t Model::find_landmark(const std::string& name) const {
    auto it = landmark_index_.find(name);
    return it == landmark_index_.end() ? int64_t{-1} : int64_t{it->second};
}

}  // namespace ssc
