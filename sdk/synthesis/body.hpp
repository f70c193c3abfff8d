// One body's state: shape coefficients and pose in, cached stage outputs out. Each stage is
// recomputed only when an input it depends on changed (shape -> rest, pose -> skeleton -> skin).
// Inputs are validated by the caller (the C API shim); setters here assume valid values.
#pragma once

#include "common/thread_pool.hpp"
#include "kernels.hpp"
#include "model.hpp"

namespace ssc {

class Body {
public:
    Body(const Model& model, const Allocator* alloc);

    const Model& model() const { return model_; }

    // Splits the shape, skinning and normals stages over the pool's threads (the same results);
    // null (the default): the calling thread only. The pool must outlive the body's use of it.
    void set_pool(ThreadPool* pool) { pool_ = pool; }

    void set_shape(const float* coeffs, uint32_t count);  // count <= K, rest zero
    const float* shape() const { return coeffs_.data(); }
    // Segment s's coefficients (count <= its components, rest zero), added to the whole-body shape.
    void set_segment_shape(uint32_t segment, const float* coeffs, uint32_t count);
    const float* segment_shape(uint32_t segment) const { return segment_coeffs_.data() + model_.segments()[segment].first; }
    void set_pose(const float* unit_quats, const float* translation);  // 4J, 3 (null = zero)

    const float* rest_planar();     // 3V: x block, y block, z block
    const float* rest_joints();     // 3J
    const float* posed();           // 3V planar: x block, y block, z block
    // The posed vertices as xyz at stride bytes (vertex v at out + v * stride): what posed() holds,
    // without making it when only this is asked for (skinned straight into out).
    void posed_xyz(float* out, std::size_t stride);
    const float* normals();         // 3V, xyz
    const float* world();           // 16J column-major
    const float* inverse_bind();    // 16J column-major
    const kernels::SkinMatrix* skinning();

    // Level of detail l of the model (Model::level; not the full mesh): its rest vertices (the
    // level's map of rest_planar()) and posed by the level's skin, planar (x block, y block, z
    // block of the level's N), and unit normals, xyz. Buffers are allocated on a level's first use.
    const float* level_rest(uint32_t l);
    const float* level_posed(uint32_t l);
    const float* level_normals(uint32_t l);

private:
    void update_rest();
    void update_skeleton();
    // The full mesh skinned in its skin layout's slot order (kernels::skin_slots_in_slot_order):
    // 3 blocks of slot_count() floats, from the rest positions in that order.
    const float* posed_slots();
    bool skin_in_slot_order() const;
    bool skin_by_blocks() const;
    // The full mesh skinned by kernels::skin_blocks (AVX-512) into xyz (packed) unless null, and
    // into posed_ when xyz is null or posed() has been used (posed_ok_ says which).
    void skin_blocks(float* xyz);
    struct LevelState {
        Vec<float> rest, posed, normals, faces;
        bool rest_ok = false, posed_ok = false, normals_ok = false;
    };
    LevelState& level_state(uint32_t l);

    // Runs fn(first, end) over [0, n) in chunks of multiples of `align`, on the pool when set.
    template <class Fn>
    void split(std::size_t n, std::size_t align, const Fn& fn);

    const Model& model_;
    ThreadPool* pool_ = nullptr;
    Vec<float> coeffs_, segment_coeffs_, scaled_, rest_, joints_, quats_, world_, inverse_bind_, posed_, normals_, scratch_, face_normals_,
        rest_slots_, posed_slots_;
    Vec<kernels::SkinMatrix> skinning_;
    const Allocator* alloc_;
    std::vector<LevelState> levels_;  // per model level, buffers empty until used
    float translation_[3] = {0, 0, 0};
    bool any_segment_ = false, rest_ok_ = false, skeleton_ok_ = false, posed_ok_ = false, normals_ok_ = false, rest_slots_ok_ = false,
         posed_slots_ok_ = false, rest_posed_ = false, rest_frames_ok_ = false;
    bool planar_used_ = false;  // posed() has been called: skin_blocks writes the planar positions too
};

}  // namespace ssc
