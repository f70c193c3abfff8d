#include "body.hpp"

#include "kernels_skin_xyz.hpp"

#include <algorithm>

namespace ssc {

Body::Body(const Model& model, const Allocator* a)
    : model_(model),
      coeffs_(model.component_count(), 0.f, CAlloc<float>(a)),
      segment_coeffs_(model.segment_coefficient_count(), 0.f, CAlloc<float>(a)),
      scaled_(model.component_count(), 0.f, CAlloc<float>(a)),
      rest_(model.padded_rows(), 0.f, CAlloc<float>(a)),
      joints_(3ull * model.joint_count(), 0.f, CAlloc<float>(a)),
      quats_(4ull * model.joint_count(), 0.f, CAlloc<float>(a)),
      world_(16ull * model.joint_count(), 0.f, CAlloc<float>(a)),
      inverse_bind_(16ull * model.joint_count(), 0.f, CAlloc<float>(a)),
      posed_(3ull * model.vertex_count(), 0.f, CAlloc<float>(a)),
      normals_(3ull * model.vertex_count(), 0.f, CAlloc<float>(a)),
      scratch_(kernels::kSkeletonScratch * model.joint_count(), 0.f, CAlloc<float>(a)),
      face_normals_(3ull * model.triangle_count(), 0.f, CAlloc<float>(a)),
      rest_slots_(CAlloc<float>(a)),
      posed_slots_(CAlloc<float>(a)),
      skinning_(model.joint_count(), kernels::SkinMatrix{}, CAlloc<kernels::SkinMatrix>(a)),
      alloc_(a),
      levels_(model.level_count()) {
    for (uint32_t j = 0; j < model.joint_count(); ++j) quats_[4 * j + 3] = 1.f;
}

void Body::set_shape(const float* coeffs, uint32_t count) {
    std::copy(coeffs, coeffs + count, coeffs_.begin());
    std::fill(coeffs_.begin() + count, coeffs_.end(), 0.f);
    rest_ok_ = skeleton_ok_ = posed_ok_ = normals_ok_ = rest_slots_ok_ = posed_slots_ok_ = rest_posed_ = rest_frames_ok_ = false;
    for (LevelState& l : levels_) l.rest_ok = l.posed_ok = l.normals_ok = false;
}

void Body::set_segment_shape(uint32_t segment, const float* coeffs, uint32_t count) {
    const SegmentSpace& s = model_.segments()[segment];
    float* c = segment_coeffs_.data() + s.first;
    std::copy(coeffs, coeffs + count, c);
    std::fill(c + count, c + s.components, 0.f);
    any_segment_ = std::any_of(segment_coeffs_.begin(), segment_coeffs_.end(), [](float x) { return x != 0.f; });
    rest_ok_ = skeleton_ok_ = posed_ok_ = normals_ok_ = rest_slots_ok_ = posed_slots_ok_ = rest_posed_ = rest_frames_ok_ = false;
    for (LevelState& l : levels_) l.rest_ok = l.posed_ok = l.normals_ok = false;
}

void Body::set_pose(const float* unit_quats, const float* translation) {
    std::copy(unit_quats, unit_quats + quats_.size(), quats_.begin());
    for (int a = 0; a < 3; ++a) translation_[a] = translation ? translation[a] : 0.f;
    skeleton_ok_ = posed_ok_ = normals_ok_ = posed_slots_ok_ = false;
    for (LevelState& l : levels_) l.posed_ok = l.normals_ok = false;
}

template <class Fn>
void Body::split(std::size_t n, std::size_t align, const Fn& fn) {
    if (!pool_ || pool_->size() == 1) return fn(std::size_t(0), n);
    // More chunks than threads: dynamic hand-out evens out a thread that starts late.
    constexpr std::size_t kChunks = 8;
    const std::size_t blocks = (n + align - 1) / align;
    pool_->parallel_for(kChunks, [&](std::size_t c, unsigned) {
        const std::size_t first = std::min(n, c * blocks / kChunks * align), end = std::min(n, (c + 1) * blocks / kChunks * align);
        if (first < end) fn(first, end);
    });
}

void Body::update_rest() {
    if (rest_ok_) return;
    kernels::scale_coefficients(model_, coeffs_.data(), scaled_.data());
    const float* c = scaled_.data();
    float* r = rest_.data();
    float* j = joints_.data();
    split(model_.padded_rows() / Model::kChunk, 1, [&](std::size_t first, std::size_t end) { kernels::shape_rows(model_, 1, &c, &r, first, end); });
    kernels::shape_joints(model_, 1, &c, &j);
    if (any_segment_)
        add_segment_shapes(model_.segments(), model_.vertex_count(), model_.joint_count(), segment_coeffs_.data(), r, j);
    rest_ok_ = true;
}

void Body::update_skeleton() {
    if (skeleton_ok_) return;
    update_rest();
    float* rest_frames = scratch_.data();
    if (!rest_frames_ok_) {  // once per shape
        kernels::skeleton_rest(model_, joints_.data(), rest_frames, inverse_bind_.data());
        rest_frames_ok_ = true;
    }
    kernels::skeleton_pose(model_, rest_frames, quats_.data(), translation_, rest_frames + kernels::kSkeletonRest * model_.joint_count(),
                           world_.data(), skinning_.data());
    skeleton_ok_ = true;
}

const float* Body::rest_planar() {
    update_rest();
    return rest_.data();
}

const float* Body::rest_joints() {
    update_rest();
    return joints_.data();
}

const float* Body::posed_slots() {
    if (!posed_slots_ok_) posed_xyz(nullptr, 0);
    return posed_slots_.data();
}

// A rest shape's first posing asked for as planar positions (posed(): normals, landmarks, fits)
// skins in vertex order (gathering and scattering inside the skinning); from its second posing on
// (an animation), the rest is put in slot order once and each posing reads and writes whole
// blocks, paying the gathers once on the way out. posed_xyz also takes slot order for a first
// posing (docs/speed.md).
bool Body::skin_in_slot_order() const { return rest_slots_ok_ || rest_posed_; }

// With AVX-512 every posing skins in vertex order by blocks of 16 vertices and their joints
// (skin_blocks.hpp): no slot order, no gathers. AVX2 and baseline x86-64 keep the slot order
// (AVX2 has no masked multiply-add: with a blend after each, blocks cost more than the gathers;
// docs/speed.md).
bool Body::skin_by_blocks() const { return kernels::skin_by_blocks(kernels::active_isa()); }

// The planar positions are written beside the caller's xyz only by a body that has used them
// (normals, landmarks, measures): one asked for its vertices alone saves their 160 KB of stores
// (pose only 16.5 -> 14.9 us, shape and pose 176 -> 169 us), and one that uses them finds them made
// from its second posing on.
void Body::skin_blocks(float* xyz) {
    update_skeleton();
    const SkinBlocks& blocks = model_.skin_blocks();
    float* planar = !xyz || planar_used_ ? posed_.data() : nullptr;
    split(blocks.block_count(), 1, [&](std::size_t first, std::size_t end) {
        kernels::skin_blocks(blocks, rest_.data(), skinning_.data(), planar, xyz, uint32_t(first), uint32_t(end), kernels::Isa::Avx512);
    });
    posed_ok_ = planar != nullptr;
}

const float* Body::posed() {
    planar_used_ = true;
    if (!posed_ok_) {
        if (skin_by_blocks()) {
            skin_blocks(nullptr);
        } else if (skin_in_slot_order()) {
            const float* slots = posed_slots();
            split(model_.vertex_count(), SkinLayout::kBlock, [&](std::size_t first, std::size_t end) {
                kernels::from_slot_order(model_.skin_layout(), slots, posed_.data(), uint32_t(first), uint32_t(end));
            });
        } else {
            update_skeleton();
            split(kernels::skin_slot_count(model_), Model::kSkinBlock, [&](std::size_t first, std::size_t end) {
                kernels::skin_slots(model_, rest_.data(), skinning_.data(), posed_.data(), uint32_t(first), uint32_t(end));
            });
            rest_posed_ = true;
        }
        posed_ok_ = true;
    }
    return posed_.data();
}

// The posed vertices into out at stride, or with out null only the skinning in slot order (what
// posed_slots() asks for). The one place that skins in slot order: a pose whose vertices are asked
// for before anything else is skinned straight into the caller's packed xyz, each block written
// while still in registers, instead of being skinned and then copied in a second pass.
void Body::posed_xyz(float* out, std::size_t stride) {
    const uint32_t V = model_.vertex_count();
    const SkinLayout& layout = model_.skin_layout();
    if (out && posed_ok_) return kernels::planar_to_xyz(posed_.data(), V, out, stride);
    if (out && posed_slots_ok_) return kernels::slots_to_xyz(layout, posed_slots_.data(), out, stride, 0, V);
    float* xyz = stride == 3 * sizeof(float) ? out : nullptr;
    if (out && skin_by_blocks()) {
        skin_blocks(xyz);
        if (!xyz) kernels::planar_to_xyz(posed_.data(), V, out, stride);
        return;
    }
    // A shape's first posing whose packed vertices are asked for first goes to slot order too: the
    // rest's conversion and the skinning straight into xyz cost less than the vertex order's
    // gathered and scattered blocks and then a copy (docs/speed.md). (posed_slots() calls this in
    // slot order only, so here out is never null.)
    if (!skin_in_slot_order() && !xyz) return kernels::planar_to_xyz(posed(), V, out, stride);
    update_skeleton();
    if (rest_slots_.empty()) {  // on first use: a body only ever asked for planar positions never pays the memory
        rest_slots_.resize(3ull * layout.slot_count());
        posed_slots_.resize(3ull * layout.slot_count());
    }
    if (!rest_slots_ok_) {  // once per shape: an animation re-poses the same rest positions
        split(layout.slot_count(), Model::kSkinBlock, [&](std::size_t first, std::size_t end) {
            kernels::to_slot_order(layout, rest_.data(), rest_slots_.data(), uint32_t(first), uint32_t(end));
        });
        rest_slots_ok_ = true;
    }
    const kernels::Isa isa = kernels::active_isa();
    split(layout.slot_count(), Model::kSkinBlock, [&](std::size_t first, std::size_t end) {
        kernels::skin_slots_and_xyz(layout, rest_slots_.data(), skinning_.data(), posed_slots_.data(), xyz, uint32_t(first), uint32_t(end), isa);
    });
    posed_slots_ok_ = true;
    if (out && !xyz) kernels::slots_to_xyz(layout, posed_slots_.data(), out, stride, 0, V);
}

const float* Body::normals() {
    if (!normals_ok_) {
        const float* p = posed();
        split(model_.triangle_count(), 1, [&](std::size_t first, std::size_t end) {
            kernels::face_normals(model_, p, face_normals_.data(), uint32_t(first), uint32_t(end));
        });
        split(model_.vertex_count(), 1, [&](std::size_t first, std::size_t end) {
            kernels::vertex_normals(model_, face_normals_.data(), normals_.data(), uint32_t(first), uint32_t(end));
        });
        normals_ok_ = true;
    }
    return normals_.data();
}

const float* Body::world() {
    update_skeleton();
    return world_.data();
}

const float* Body::inverse_bind() {
    update_skeleton();
    return inverse_bind_.data();
}

const kernels::SkinMatrix* Body::skinning() {
    update_skeleton();
    return skinning_.data();
}

Body::LevelState& Body::level_state(uint32_t l) {
    LevelState& s = levels_[l];
    if (s.rest.empty()) {
        const std::size_t n = 3ull * model_.level(l).vertex_count;
        s.rest = Vec<float>(n, 0.f, CAlloc<float>(alloc_));
        s.posed = Vec<float>(n, 0.f, CAlloc<float>(alloc_));
        s.normals = Vec<float>(n, 0.f, CAlloc<float>(alloc_));
        s.faces = Vec<float>(3ull * model_.level(l).triangle_count(), 0.f, CAlloc<float>(alloc_));
    }
    return s;
}

const float* Body::level_rest(uint32_t l) {
    LevelState& s = level_state(l);
    if (!s.rest_ok) {
        levels::from_body(model_.level(l), rest_planar(), model_.vertex_count(), s.rest.data());
        s.rest_ok = true;
    }
    return s.rest.data();
}

const float* Body::level_posed(uint32_t l) {
    LevelState& s = level_state(l);
    if (!s.posed_ok) {
        const float* rest = level_rest(l);
        kernels::skin_slots(model_.level_skin(l), rest, skinning(), s.posed.data(), 0, model_.level_skin(l).slot_count(), kernels::active_isa());
        s.posed_ok = true;
    }
    return s.posed.data();
}

const float* Body::level_normals(uint32_t l) {
    LevelState& s = level_state(l);
    if (!s.normals_ok) {
        const float* posed = level_posed(l);
        levels::normals(model_.level(l), model_.level_topology(l), posed, s.faces.data(), s.normals.data());
        s.normals_ok = true;
    }
    return s.normals.data();
}

}  // namespace ssc
