// The decoded contents of a .sscape file: plain data, exactly what the file says, checked by
// validate_model(). Writers fill it (quantizing the basis with quantize_basis), the reader
// produces it, and the runtime builds its derived, synthesis-ready model from it.
#pragma once

#include "common/alloc.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::format {

struct Metadata {
    std::string name, model_version, units = "m", axes = "right-handed, +Y up, +Z forward", license,
        provenance, description;
};

struct Mesh {
    uint32_t vertex_count = 0;
    Vec<uint32_t> triangles;     // 3 per triangle
    Vec<uint32_t> quads;         // 4 per quad, optional
    Vec<float> uvs;              // 2 per coordinate, optional
    Vec<uint32_t> triangle_uvs;  // 3 per triangle when uvs exist
    Vec<uint32_t> quad_uvs;      // 4 per quad when uvs and quads exist
};

// Basis B_k (metres per standard deviation) = step[k] * q, planar layout:
// q[k * 3V + axis * V + v] for component k, axis 0..2 (x, y, z), vertex v.
struct QuantizedBasis {
    uint32_t components = 0;
    Vec<float> step;   // per component, > 0
    Vec<int16_t> q;
};

struct ShapeSpace {
    Vec<float> mean;      // 3 per vertex, interleaved xyz
    Vec<float> stddev;    // per component
    QuantizedBasis basis;
};

struct Skeleton {
    std::vector<std::string> joint_names;
    Vec<int32_t> parents;
    Vec<float> rest_orientations;  // xyzw per joint
    Vec<uint32_t> regressor_offsets;
    Vec<uint32_t> regressor_vertices;
    Vec<float> regressor_weights;
};

struct Skin {
    Vec<uint16_t> joints;  // 4 per vertex
    Vec<float> weights;    // 4 per vertex
};

inline constexpr uint32_t kNone = 0xFFFFFFFFu;

struct Landmark {
    std::string name;
    uint32_t vertex = kNone;    // either a vertex ...
    uint32_t triangle = kNone;  // ... or a triangle with barycentric weights
    float barycentric[3] = {0, 0, 0};
};

struct VertexSet {
    std::string name;
    Vec<uint32_t> vertices;
};

// See the schema (JointLimit) for the convention.
struct JointLimit {
    uint32_t joint = 0;
    float frame[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
    float lower[3] = {0, 0, 0}, upper[3] = {0, 0, 0};  // radians
};

// See the schema (JointRole).
struct JointRole {
    uint8_t part = 0;             // 0 torso, 1 head, 2 arm, 3 hand, 4 leg, 5 foot
    uint8_t side = 0;             // 0 centre, 1 left, 2 right
    double rotation_sigma = 0.6;  // radians
    bool coarse = false;
    uint8_t limb_joint = 0;       // 0 none, 1 upper, 2 middle
};

struct Attribute {
    std::string name, unit, description;
    float mean = 0, minimum = 0, maximum = 0;
    bool slider = false;
};

// See the schema (AttributeModel). Empty when the model has none.
struct AttributeModel {
    std::vector<Attribute> attributes;
    std::vector<float> covariance;        // A x A, row-major
    std::vector<float> shape_covariance;  // A x K, row-major
};

// See the schema (ShapeSegment). basis is planar over the segment's own vertices:
// q[k * 3n + axis * n + i] for vertex vertices[i].
struct ShapeSegment {
    std::string name;
    std::vector<uint32_t> vertices;  // sorted, unique
    std::vector<float> weights;      // per vertex, in [0, 1]; summed over segments at most 1
    std::vector<float> stddev;       // per component
    QuantizedBasis basis;
};

// See the schema (DetailLevel). 4 entries per level vertex in sources, source_weights, skin_joints
// and skin_weights.
struct DetailLevel {
    std::string name;
    uint32_t vertex_count = 0;
    std::vector<uint32_t> sources;
    std::vector<float> source_weights;
    std::vector<uint32_t> triangles;
    std::vector<float> uvs;                   // optional
    std::vector<uint32_t> triangle_uvs;       // with uvs
    std::vector<uint16_t> skin_joints;
    std::vector<float> skin_weights;
    std::vector<uint32_t> landmark_triangles;   // one per model landmark
    std::vector<float> landmark_barycentric;    // 3 per model landmark

    uint32_t triangle_count() const { return static_cast<uint32_t>(triangles.size() / 3); }
};

struct ModelData {
    Metadata metadata;
    Mesh mesh;
    ShapeSpace shape;
    Skeleton skeleton;
    Skin skin;
    std::vector<Landmark> landmarks;
    std::vector<VertexSet> vertex_sets;
    std::vector<JointLimit> joint_limits;  // sorted by joint, at most one per joint
    AttributeModel attributes;
    std::vector<JointRole> joint_roles;    // one per joint, or empty (the runtime's table by names)
    std::vector<ShapeSegment> segments;    // segment shape spaces, optional
    std::vector<DetailLevel> levels;       // levels of detail, finest first, optional

    uint32_t vertex_count() const { return mesh.vertex_count; }
    uint32_t joint_count() const { return static_cast<uint32_t>(skeleton.parents.size()); }
    uint32_t component_count() const { return shape.basis.components; }
};

// Checks every semantic rule of the format (sizes, index ranges, finite numbers, normalised weights,
// parent order, unique names). Throws ssc::Error(SSC_ERROR_MODEL_CORRUPT) naming the first problem.
void validate_model(const ModelData& m);

}  // namespace ssc::format
