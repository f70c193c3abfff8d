// The far ends of a body on its surface, whatever its pose: head, hands and feet are where the
// distance along the surface from everything else peaks, and those distances do not change when
// the joints bend (a person's surface bends, it does not stretch). The start search uses them to
// place a body it has no template pose for (solver.cpp, docs/fitting.md "Extremities"):
//
//   scan: a neighbour graph of the points, geodesic farthest-point picks (the extremities);
//   model: the mean body's mesh at rest, each tip the vertex of its part farthest from the trunk;
//   labelling: which extremity is which tip, by comparing the two sets' geodesic distances.
//
// Geodesics cannot tell left from right (a mirrored labelling has the same distances): the
// labellings come with their mirror images, and the fit that follows tells them apart.
#pragma once

#include "fitting/kinematics.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssc::fitting {

using Eigen::Vector3d;

// The tips, in this order: head (the crown), left and right hand (the middle fingertip), left and
// right foot (the toes).
constexpr std::size_t kTipCount = 5;

// Shortest paths over a graph of surface points (edge lengths in metres).
struct SurfaceGraph {
    std::vector<Vector3d> nodes;
    std::vector<uint32_t> offsets;  // node i's edges: [offsets[i], offsets[i + 1])
    std::vector<uint32_t> targets;
    std::vector<double> lengths;
};

// Pieces of a scan graph smaller than this (stray points, clutter) are not joined to the rest.
constexpr std::size_t kMinPiece = 12;

// The graph of a scan: its points thinned to one per `spacing` cube, each joined to its nearest
// neighbours within kReach spacings unless their normals face each other (two surfaces touching:
// a hand on a thigh, thighs against the chest); pieces cut off by holes joined to the rest by
// their shortest gap (pieces under kMinPiece nodes, stray points, stay apart). normals: unit or
// zero (unknown), as many as points, or empty.
constexpr double kReach = 2.0;
SurfaceGraph scan_graph(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, double spacing);
// The graph of a triangle mesh's edges.
SurfaceGraph mesh_graph(const std::vector<Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count);
// Geodesic distance of every node from the nearest of `sources` (infinity where unreachable);
// previous: each node's predecessor on its shortest path (itself for a source or unreached).
std::vector<double> geodesic_from(const SurfaceGraph& graph, const std::vector<uint32_t>& sources,
                                  std::vector<uint32_t>* previous = nullptr);

// How far back from a hand's tip its guide lies (metres on the mean body, scaled on a scan): the
// palm. A fingertip drawn to its place turns the forearm to point the hand, and the wrist, which
// the start does not move, cannot (the thumb ended on the wrong side of standing scans).
constexpr double kPalmBack = 0.10;

// A scan's extremities: geodesic farthest-point picks, most distant first (each the farthest
// along the surface from the picks before it; the first from the scan's centre). On a person the
// tips come first (0.6 to 1.7 m from the picks before them), then elbows, knees and shoulders.
struct ScanExtremities {
    std::vector<Vector3d> points;
    Eigen::MatrixXd geodesic;  // between the picks, metres
    // Each pick's shortest path towards the scan's centre (its first kPathLength metres): nodes and
    // their distances from the pick.
    std::vector<std::vector<std::pair<double, Vector3d>>> paths;
    // The point `distance` back along pick i's path (its end when shorter).
    Vector3d back_along(std::size_t i, double distance) const;
};
constexpr double kPathLength = 0.3;
ScanExtremities scan_extremities(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, std::size_t count,
                                 double spacing = 0.025);

// The model's tips: a vertex per tip on the mean body at rest and their geodesic distances.
struct ModelTips {
    std::array<uint32_t, kTipCount> vertex{};
    std::array<uint32_t, kTipCount> guide{};  // the vertex the start draws: the tip's, the palm for the hands
    Eigen::Matrix<double, kTipCount, kTipCount> geodesic = Eigen::Matrix<double, kTipCount, kTipCount>::Zero();
    bool valid = false;  // false for a model whose parts lack a tip (no head, arms or legs)
};
// Each vertex's tip part (the tip's index: the head with the neck, each arm with its hand, each leg
// with its foot, by the vertex's dominant joint's role) or kNoTip (the trunk).
constexpr uint8_t kNoTip = 255;
std::vector<uint8_t> tip_parts(const LinearModel& lin);
// vertices: the mean body at rest; parts: tip_parts(). Each tip is its part's vertex farthest
// along the surface from the trunk's centre.
ModelTips model_tips(const std::vector<Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count,
                     const std::vector<uint8_t>& parts);

// Which extremity is which tip (-1: the tip was not found, such as a hand resting on the body).
struct TipLabelling {
    std::array<int, kTipCount> extremity{};
    double scale = 1;  // scan geodesics over the model's
    double cost = 0;   // mean squared relative geodesic mismatch plus the missing tips' penalty
};
// The labellings of at least kMinTips tips whose geodesic distances agree best with the model's,
// best first, each followed by its mirror images (left and right swapped for the hands and feet:
// the person facing the other way; then for the hands alone, the feet alone): at most `keep`
// distinct ones. Empty when the scan has too few extremities or none costs kMaxLabelCost or less.
constexpr std::size_t kMinTips = 4;
// Labellings costing more are no person's (on the pose library's booth scans the right ones cost
// under 0.035): a ball, a crate or two people get none.
constexpr double kMaxLabelCost = 0.05;
std::vector<TipLabelling> label_extremities(const ScanExtremities& scan, const ModelTips& model, std::size_t keep);

}  // namespace ssc::fitting
