// Segment shape spaces (PCA per body segment, after the second S-SCAPE paper): the body cut into
// head, arms, torso and legs by the model's body-part vertex sets, overlapping bands around the
// borders where blend weights fall smoothly (geodesic distance over the mesh edges), and a PCA of
// each segment's vertices over the same aligned bodies as the whole-body space.
#pragma once

#include "sscape_format/model_data.hpp"
#include "training/pca.hpp"

#include <string>
#include <vector>

namespace ssc::training {

// Which vertices each segment moves and with what blend weight.
struct SegmentLayout {
    std::string name;
    std::vector<uint32_t> vertices;  // sorted
    std::vector<float> weights;      // in (0, 1]; over all segments they sum to 1 at every vertex
};

// The six segments head, arm_l, arm_r, torso, leg_l, leg_r from the vertex sets head, torso, arms,
// hands, legs and feet (hands join their arm, feet their leg; the side is the sign of x on the mean,
// +X being the body's left). band: metres on each side of a border over which a vertex's weight goes
// from its own segment to its neighbour's. Throws ssc::Error (INVALID_ARGUMENT) for a model without
// those vertex sets or a band outside [0, 0.5] m.
std::vector<SegmentLayout> segment_layout(const format::ModelData& model, double band);

struct SegmentSpec {
    uint32_t components = 10;   // per segment; at most bodies - 1
    double band = 0.08;         // metres, see segment_layout
    double tolerance = 1e-4;    // basis quantization bound, metres
    uint32_t seed = 1;          // randomized SVD
};

// How much of a segment's variance (over the training bodies) its own first k components hold,
// beside the whole body's first k components: index k - 1 for k = 1..K.
struct SegmentCompactness {
    std::string name;
    uint32_t vertices = 0;
    double variance = 0;                 // the segment's total, m^2 per body
    std::vector<double> own, whole_body; // shares in [0, 1]
};

// The segments' shape spaces over the bodies in the first `rows` rows of X (x y z per vertex,
// centred on `mean`-less displacement: what pca() leaves in X). whole: the whole-body PCA of the
// same rows, for the compactness comparison. Throws ssc::Error (INVALID_ARGUMENT) as segment_layout,
// or for components outside [1, rows - 1].
std::vector<format::ShapeSegment> learn_segments(const format::ModelData& model, const SampleMatrix& centred, Eigen::Index rows,
                                                 const Pca& whole, const SegmentSpec& spec,
                                                 std::vector<SegmentCompactness>* compactness = nullptr);

}  // namespace ssc::training
