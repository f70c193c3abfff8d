// The runtime model: the decoded file plus what synthesis derives from it once at load
// (planar mean, joint regressor applied to the mean and the basis, name lookups). Immutable after
// construction and shared by every body; reference counted by the C API shim.
#pragma once

#include "common/alloc.hpp"
#include "levels.hpp"
#include "segments.hpp"
#include "skin_blocks.hpp"
#include "skin_layout.hpp"
#include "sscape_format/model_data.hpp"

#include <string>
#include <unordered_map>
#include <vector>

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

    // The skinning layout (skin_layout.hpp): the mesh's, and each level of detail's.
    static constexpr uint32_t kSkinBlock = SkinLayout::kBlock;
    using SkinRun = SkinLayout::Run;
    const SkinLayout& skin_layout() const { return skin_layout_; }
    const SkinBlocks& skin_blocks() const { return skin_blocks_; }
    const std::vector<SkinRun>& skin_runs() const { return skin_layout_.runs; }
    const uint32_t* skin_vertices() const { return skin_layout_.vertices.data(); }    // per slot
    const float* skin_weights(int i) const { return skin_layout_.weights[i].data(); }  // per slot, influence i
    const uint8_t* skin_block_contiguous() const { return skin_layout_.contiguous.data(); }  // per block

    // Triangles around each vertex (CSR): normals gather face normals per vertex instead of
    // scattering into shared vertices, which stalls on store forwarding.
    const uint32_t* vertex_triangle_offsets() const { return vt_offsets_.data(); }  // V + 1
    const uint32_t* vertex_triangles() const { return vt_triangles_.data(); }

    // Segment shape spaces (may be none); a body's segment coefficients are all segments' in order.
    const std::vector<SegmentSpace>& segments() const { return segments_; }
    uint32_t segment_coefficient_count() const { return segment_coefficients_; }

    // Levels of detail (may be none): the file's (data().levels) and what synthesis derives from each.
    uint32_t level_count() const { return static_cast<uint32_t>(data_.levels.size()); }
    const format::DetailLevel& level(uint32_t l) const { return data_.levels[l]; }
    const LevelTopology& level_topology(uint32_t l) const { return level_topology_[l]; }
    const SkinLayout& level_skin(uint32_t l) const { return level_skin_[l]; }

    // One mesh of the model by level, as plain arrays: 0 the full mesh, l > 0 level(l - 1). What
    // the C API and the exporters read, so "level 0 is the full mesh" is decided here once.
    struct LevelMesh {
        const char* name;
        uint32_t vertex_count, triangle_count, uv_count;
        const uint32_t* triangles;                 // 3 per triangle
        const float* uvs;                          // 2 per coordinate, null without UVs
        const uint32_t* triangle_uvs;              // 3 per triangle, null without UVs
        const uint16_t* skin_joints;               // 4 per vertex
        const float* skin_weights;                 // 4 per vertex
    };
    LevelMesh level_mesh(uint32_t level) const;    // level <= level_count()

    // -1 when absent.
    int64_t find_joint(const std::string& name) const;
    int64_t find_landmark(const std::string& name) const;
    int64_t find_segment(const std::string& name) const;

private:
    format::ModelData data_;
    uint32_t V_, K_, J_;
    std::size_t padded_rows_;
    Vec<int16_t> basis_panels_;
    Vec<float> mean_planar_, joint_mean_, joint_basis_, landmark_rest_;
    SkinLayout skin_layout_;
    SkinBlocks skin_blocks_;
    Vec<uint32_t> vt_offsets_, vt_triangles_;
    std::vector<SegmentSpace> segments_;
    uint32_t segment_coefficients_ = 0;
    std::vector<LevelTopology> level_topology_;
    std::vector<SkinLayout> level_skin_;
    std::unordered_map<std::string, uint32_t> joint_index_, landmark_index_;
};

}  // namespace ssc
