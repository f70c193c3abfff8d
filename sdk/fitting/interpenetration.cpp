#include "fitting/interpenetration.hpp"

#include "anatomy/joint_roles.hpp"
#include "fitting/nearest.hpp"

#include <algorithm>
#include <memory>

namespace ssc::fitting {

namespace {
// Every this many vertices are tested and make up the parts' surfaces (about 1.5 cm apart).
constexpr uint32_t kStride = 2;
}  // namespace

InterpenetrationTest::InterpenetrationTest(const LinearModel& lin) : regions_(vertex_regions(lin)) {
    // The middle joint (elbow, knee) of each limb region: a vertex is distal when its dominant
    // joint is that joint or below it.
    std::array<int64_t, kBodyRegionCount> middle;
    middle.fill(-1);
    using anatomy::BodyPart;
    using anatomy::Side;
    const struct {
        BodyRegion region;
        BodyPart part;
        Side side;
    } limbs[] = {{BodyRegion::LeftArm, BodyPart::Arm, Side::Left},
                 {BodyRegion::RightArm, BodyPart::Arm, Side::Right},
                 {BodyRegion::LeftLeg, BodyPart::Leg, Side::Left},
                 {BodyRegion::RightLeg, BodyPart::Leg, Side::Right}};
    for (const auto& l : limbs)
        middle[std::size_t(l.region)] = anatomy::find_limb_joint(lin.roles, l.part, l.side, anatomy::LimbJoint::Middle);
    for (uint32_t v = 0; v < lin.V; v += kStride) {
        const std::size_t r = regions_[v];
        if (r >= kBodyRegionCount) continue;
        surface_[r].push_back(v);
        if (middle[r] < 0) continue;
        const uint32_t j = dominant_joint(lin.model.data(), v);
        if (j >= lin.chains.size()) continue;
        const auto& chain = lin.chains[j];
        if (std::find(chain.begin(), chain.end(), uint32_t(middle[r])) != chain.end()) tested_.push_back(v);
    }
}

LimbsInside InterpenetrationTest::measure(const std::vector<Vector3d>& vertices, const std::vector<Vector3d>& normals) const {
    LimbsInside result;
    std::array<std::vector<Vector3d>, kBodyRegionCount> points;
    std::array<std::unique_ptr<PointIndex>, kBodyRegionCount> index;
    for (std::size_t r = 0; r < kBodyRegionCount; ++r) {
        for (uint32_t v : surface_[r]) points[r].push_back(vertices[v]);
        if (!points[r].empty()) index[r] = std::make_unique<PointIndex>(points[r]);
    }
    std::array<std::size_t, kBodyRegionCount> tested{};
    std::array<std::array<std::size_t, kBodyRegionCount>, kBodyRegionCount> inside{};  // [limb][part]
    std::array<std::size_t, kBodyRegionCount> inside_any{};
    for (uint32_t v : tested_) {
        const std::size_t a = regions_[v];
        ++tested[a];
        bool any = false;
        for (std::size_t b = 0; b < kBodyRegionCount; ++b) {
            if (b == a || !index[b]) continue;
            double d2;
            const uint32_t k = index[b]->nearest(vertices[v], &d2);
            if (d2 > kInsideReach * kInsideReach) continue;
            const uint32_t u = surface_[b][k];
            if ((vertices[u] - vertices[v]).dot(normals[u]) > kInsideDepth) ++inside[a][b], any = true;
        }
        inside_any[a] += any;
    }
    for (std::size_t a = 0; a < kBodyRegionCount; ++a) {
        if (tested[a] == 0) continue;
        result.share[a] = double(inside_any[a]) / double(tested[a]);
        if (result.share[a] > result.worst) {
            result.worst = result.share[a], result.limb = int32_t(a);
            result.part = int32_t(std::max_element(inside[a].begin(), inside[a].end()) - inside[a].begin());
        }
    }
    return result;
}

}  // namespace ssc::fitting
