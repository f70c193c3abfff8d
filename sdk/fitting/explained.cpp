#include "fitting/explained.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace ssc::fitting {

double explained_term(const CloudView& cloud, uint32_t i, const Vector3d& x, const Vector3d& n, double cap2) {
    if (!normals_agree((*cloud.normals)[i], n, cloud.oriented, 0.0)) return cap2;
    return std::min(((*cloud.points)[i] - x).squaredNorm(), cap2);
}

double model_term(const CloudView& cloud, const Vector3d& x, const Vector3d& n, double cap) {
    const uint32_t i = cloud.grid->nearest(x, cap, nullptr);
    return i == GridIndex::kNone ? cap * cap : explained_term(cloud, i, x, n, cap * cap);
}

double explained_measure(const CloudView& cloud, const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals,
                         const std::function<uint32_t(const Vector3d&)>& nearest_model, double cap, std::size_t samples) {
    const double cap2 = cap * cap;
    double sum = 0;
    const std::size_t n = std::min(cloud.sample->size(), samples);
    for (std::size_t s = 0; s < n; ++s) {
        const uint32_t i = (*cloud.sample)[s];
        const uint32_t k = nearest_model((*cloud.points)[i]);
        sum += k == GridIndex::kNone ? cap2 : explained_term(cloud, i, points[k], normals[k], cap2);
    }
    const std::size_t m = std::min(points.size(), samples);
    for (std::size_t k = 0; k < m; ++k) sum += model_term(cloud, points[k], normals[k], cap);
    return sum;
}

LimbScore::LimbScore(const Kinematics& kin, const CloudView& cloud, const std::vector<uint32_t>& vertices,
                     const std::vector<Vector3d>& posed, const std::vector<Vector3d>& posed_normals, uint32_t joint, double cap,
                     double model_cap, std::size_t samples)
    : cloud_(cloud), cap2_(cap * cap), model_cap_(model_cap) {
    const Model& model = kin.model();
    const auto& skin = model.data().skin;
    const auto& parents = model.data().skeleton.parents;
    // Joints at or below `joint` (parents precede children).
    std::vector<uint8_t> below(model.joint_count(), 0);
    for (uint32_t j = 0; j < below.size(); ++j) below[j] = j == joint || (parents[j] >= 0 && below[uint32_t(parents[j])]);
    const std::size_t m = std::min(vertices.size(), samples);
    std::vector<Vector3d> fixed;
    std::vector<uint32_t> fixed_vertex;
    for (std::size_t s = 0; s < vertices.size(); ++s) {
        const uint32_t v = vertices[s];
        bool moves = false;
        for (int i = 0; i < 4; ++i) moves |= skin.weights[4 * std::size_t(v) + i] != 0 && below[skin.joints[4 * std::size_t(v) + i]];
        if (moves) {
            moving_.push_back(v);
            Influence inf;
            for (int i = 0; i < 4; ++i) inf.joint[i] = skin.joints[4 * std::size_t(v) + i], inf.weight[i] = skin.weights[4 * std::size_t(v) + i];
            influence_.push_back(inf);
            moving_scored_.push_back(s < m);
            unposed_.push_back(kin.rest_vertex(v));
            rest_normal_.push_back(kin.skin_rotation(v).inverse() * posed_normals[v]);
        } else {
            fixed.push_back(posed[v]);
            fixed_vertex.push_back(v);
            if (s < m) fixed_sum_ += model_term(cloud, posed[v], posed_normals[v], model_cap);
        }
    }
    GridIndex index(0.04);  // the sample's spacing is about 2.5 cm
    index.build(fixed);
    // Metres: the limb could lower such a term by at most this squared, small beside the cap. At
    // 1 cm most scan points stayed open (the sample is 2.5 cm apart) and cost a query per
    // candidate; 3 cm made the same choices on the benchmark for 2 % fewer instructions.
    constexpr double kSettled = 0.03;
    const std::size_t n = std::min(cloud.sample->size(), samples);
    for (std::size_t s = 0; s < n; ++s) {
        const uint32_t i = (*cloud.sample)[s];
        double d2 = std::numeric_limits<double>::infinity(), term = cap2_;
        const uint32_t k = index.nearest((*cloud.points)[i], cap, &d2);
        if (k != GridIndex::kNone) term = explained_term(cloud, i, fixed[k], posed_normals[fixed_vertex[k]], cap2_);
        if (d2 < kSettled * kSettled && term < cap2_) {
            fixed_sum_ += term;
            continue;
        }
        open_.push_back(i);
        fixed_d2_.push_back(d2);
        fixed_term_.push_back(term);
    }
}

double LimbScore::operator()(const Kinematics& kin, double bound) {
    const std::size_t nm = moving_.size();
    posed_.resize(nm);
    normals_.resize(nm);
    double sum = fixed_sum_;
    for (std::size_t i = 0; i < nm; ++i) {
        // The blended skinning transform serves both the position and the normal.
        const Influence& inf = influence_[i];
        Matrix3d M = Matrix3d::Zero();
        Vector3d t = Vector3d::Zero();
        for (int a = 0; a < 4; ++a) {
            if (inf.weight[a] == 0) continue;
            M += inf.weight[a] * kin.joint_skin_rotation(inf.joint[a]);
            t += inf.weight[a] * kin.joint_skin_translation(inf.joint[a]);
        }
        posed_[i] = kin.scale() * (M * unposed_[i] + t) + kin.translation();
        normals_[i] = (M * rest_normal_[i]).normalized();
        if (moving_scored_[i]) {
            sum += model_term(cloud_, posed_[i], normals_[i], model_cap_);
            if (sum >= bound) return sum;
        }
    }
    if (nm == 0) {
        for (double t : fixed_term_) sum += t;
        return sum;
    }
    // Each open scan point is explained by its nearest model vertex, fixed or moved. Moved ones
    // farther than the fixed one, or than the cap, would not change its term: the search stops there.
    moved_index_.build(posed_);
    for (std::size_t s = 0; s < open_.size(); ++s) {
        const uint32_t i = open_[s];
        const double radius = std::sqrt(std::min(fixed_d2_[s], cap2_));
        const uint32_t k = moved_index_.nearest((*cloud_.points)[i], radius, nullptr);
        sum += k != GridIndex::kNone ? explained_term(cloud_, i, posed_[k], normals_[k], cap2_) : fixed_term_[s];
        if (sum >= bound) return sum;
    }
    return sum;
}

}  // namespace ssc::fitting
