#include "scan_normals.hpp"

#include <Eigen/Eigenvalues>

#include <cstdint>

namespace ssc::fitting {

bool estimate_missing_normals(const std::vector<Eigen::Vector3d>& points, const PointIndex& index, std::vector<Eigen::Vector3d>& normals) {
    std::vector<uint8_t> given(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) given[i] = normals[i].squaredNorm() > 0;
    bool oriented = true;
    uint32_t idx[12];
    double d2[12];
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (given[i]) continue;
        const std::size_t n = index.nearest_k(points[i], 12, idx, d2);
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < n; ++k) c += points[idx[k]];
        c /= double(n);
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (std::size_t k = 0; k < n; ++k) cov += (points[idx[k]] - c) * (points[idx[k]] - c).transpose();
        // With fewer than 3 neighbours the plane is undetermined: any unit vector will do, unsigned.
        const Eigen::Vector3d normal =
            n >= 3 ? Eigen::Vector3d(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0)) : Eigen::Vector3d::UnitZ();
        double vote = 0;
        for (std::size_t k = 0; k < n; ++k)
            if (given[idx[k]]) vote += normal.dot(normals[idx[k]]);
        oriented = oriented && vote != 0 && n >= 3;
        normals[i] = vote < 0 ? Eigen::Vector3d(-normal) : normal;
    }
    return oriented;
}

}  // namespace ssc::fitting
