// Nearest-neighbour queries over a point set (nanoflann k-d tree). The points are referenced, not
// copied: they must outlive the index and stay unchanged while it is used.
#pragma once

#include <Eigen/Core>
#include <nanoflann.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace ssc::fitting {

class PointIndex {
public:
    explicit PointIndex(const std::vector<Eigen::Vector3d>& points) : adaptor_{&points} {
        tree_ = std::make_unique<Tree>(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
        tree_->buildIndex();
    }

    std::size_t size() const { return adaptor_.points->size(); }

    // Index of the nearest point and its squared distance.
    uint32_t nearest(const Eigen::Vector3d& q, double* dist2) const {
        uint32_t index = 0;
        double d2 = 0;
        tree_->knnSearch(q.data(), 1, &index, &d2);
        if (dist2) *dist2 = d2;
        return index;
    }

    // Up to k nearest (fewer when the set is smaller); returns how many were found.
    std::size_t nearest_k(const Eigen::Vector3d& q, std::size_t k, uint32_t* index, double* dist2) const {
        return tree_->knnSearch(q.data(), k, index, dist2);
    }

private:
    struct Adaptor {
        const std::vector<Eigen::Vector3d>* points;
        std::size_t kdtree_get_point_count() const { return points->size(); }
        double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][int(dim)]; }
        template <class BBox>
        bool kdtree_get_bbox(BBox&) const { return false; }
    };
    using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3, uint32_t>;
    Adaptor adaptor_;
    std::unique_ptr<Tree> tree_;
};

}  // namespace ssc::fitting
