#include "skeleton_fit.hpp"

#include "common/error.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

namespace ssc::training {
namespace {

Eigen::Vector3d joint_position(const mh::Assets& a, const mh::Rig& rig, const std::string& joint, const std::vector<float>& xyz) {
    const auto it = rig.joints.find(joint);
    if (it == rig.joints.end() || it->second.empty()) fail(SSC_ERROR_IO, "rig joint '" + joint + "' has no vertices");
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (uint32_t v : it->second) {
        if (v >= a.base.vertex_count) fail(SSC_ERROR_IO, "rig joint '" + joint + "' names a vertex out of range");
        p += Eigen::Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    }
    return p / double(it->second.size());
}

}  // namespace

std::vector<float> game_joint_positions(const mh::Assets& a, const std::vector<float>& xyz) {
    std::vector<float> out;
    for (const auto& b : a.game_rig.bones) {
        const Eigen::Vector3d p = joint_position(a, a.game_rig, b.head, xyz);
        out.insert(out.end(), {float(p.x()), float(p.y()), float(p.z())});
    }
    return out;
}

Regressor learn_regressor(const SampleMatrix& bodies, const SampleMatrix& joints, uint32_t support, uint32_t heldout) {
    const Eigen::Index N = bodies.rows(), V = bodies.cols() / 3, J = joints.cols() / 3;
    const Eigen::Index fit = N - Eigen::Index(heldout);
    if (fit < 2) fail(SSC_ERROR_INVALID_ARGUMENT, "too few bodies to learn a joint regressor");
    const Eigen::RowVectorXf mean_body = bodies.topRows(fit).colwise().mean();
    const Eigen::RowVectorXf mean_joint = joints.topRows(fit).colwise().mean();
    Regressor r;
    r.offsets.push_back(0);
    std::vector<double> errors;
    for (Eigen::Index j = 0; j < J; ++j) {
        const Eigen::Vector3f mj = mean_joint.segment<3>(3 * j).transpose();
        // Support: the nearest vertices in each of the 6 axis directions (a 60-degree cone each),
        // so the joint sits inside its support and is interpolated rather than extrapolated,
        // which matters for joints deep in the torso. Duplicates are merged.
        std::vector<uint32_t> idx;
        const uint32_t per_side = std::max<uint32_t>(1, support / 6);
        for (int axis = 0; axis < 3; ++axis)
            for (float sign : {-1.f, 1.f}) {
                std::vector<std::pair<float, uint32_t>> cone;
                for (Eigen::Index v = 0; v < V; ++v) {
                    const Eigen::Vector3f d = mean_body.segment<3>(3 * v).transpose() - mj;
                    const float n = d.norm();
                    if (n > 0 && sign * d[axis] > 0.5f * n) cone.emplace_back(n, uint32_t(v));
                }
                const std::size_t take = std::min<std::size_t>(per_side, cone.size());
                std::partial_sort(cone.begin(), cone.begin() + take, cone.end());
                for (std::size_t i = 0; i < take; ++i) idx.push_back(cone[i].second);
            }
        std::sort(idx.begin(), idx.end());
        idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
        const uint32_t S = uint32_t(idx.size());
        // w = 1/S + u with sum(u) = 0: u = P z, P an orthonormal basis of sum-zero vectors; ridge on u
        // keeps the weights near uniform unless the data ask otherwise.
        // The last S - 1 columns of a QR of the ones vector span exactly the sum-zero vectors.
        Eigen::HouseholderQR<Eigen::MatrixXd> qr(Eigen::MatrixXd::Ones(S, 1));
        const Eigen::MatrixXd basis = (qr.householderQ() * Eigen::MatrixXd::Identity(S, S)).rightCols(S - 1);
        Eigen::MatrixXd A(3 * fit, S);
        Eigen::VectorXd y(3 * fit);
        double scale = 0;
        for (Eigen::Index b = 0; b < fit; ++b)
            for (int c = 0; c < 3; ++c) {
                double uniform = 0;
                for (uint32_t s = 0; s < S; ++s) {
                    A(3 * b + c, s) = bodies(b, 3 * idx[s] + c);
                    uniform += A(3 * b + c, s) / S;
                }
                y(3 * b + c) = joints(b, 3 * j + c) - uniform;
                scale += A.row(3 * b + c).squaredNorm();
            }
        const Eigen::MatrixXd AB = A * basis;
        const double lambda = 1e-6 * scale / S;
        const Eigen::VectorXd z = (AB.transpose() * AB + lambda * Eigen::MatrixXd::Identity(S - 1, S - 1)).ldlt().solve(AB.transpose() * y);
        const Eigen::VectorXd w = Eigen::VectorXd::Constant(S, 1.0 / S) + basis * z;
        for (uint32_t s = 0; s < S; ++s) {
            r.vertices.push_back(idx[s]);
            r.weights.push_back(float(w(s)));
        }
        // Make the stored float weights sum to 1 exactly enough for validation.
        double sum = 0;
        for (uint32_t s = 0; s < S; ++s) sum += r.weights[r.weights.size() - S + s];
        r.weights.back() += float(1.0 - sum);
        r.offsets.push_back(uint32_t(r.vertices.size()));
        double joint_sum = 0;
        for (Eigen::Index b = fit; b < N; ++b) {
            Eigen::Vector3d p = Eigen::Vector3d::Zero();
            for (uint32_t s = 0; s < S; ++s) p += double(r.weights[r.offsets[j] + s]) * bodies.row(b).segment<3>(3 * idx[s]).transpose().cast<double>();
            errors.push_back((p - joints.row(b).segment<3>(3 * j).transpose().cast<double>()).norm());
            joint_sum += errors.back();
        }
        r.joint_mean_error.push_back(N > fit ? joint_sum / double(N - fit) : 0.0);
    }
    if (!errors.empty()) {
        r.heldout_mean_error = std::accumulate(errors.begin(), errors.end(), 0.0) / double(errors.size());
        r.heldout_max_error = *std::max_element(errors.begin(), errors.end());
    }
    return r;
}

void game_skin_weights(const mh::Assets& a, std::vector<uint16_t>& joints, std::vector<float>& weights) {
    // Default bone -> game bone: the game bone that lists it (weights_reference, else reference);
    // a default bone no game bone lists goes with its nearest listed ancestor.
    std::map<std::string, int> game_of;
    for (std::size_t g = 0; g < a.game_rig.bones.size(); ++g) {
        const auto& b = a.game_rig.bones[g];
        for (const auto& d : b.weights_reference.empty() ? b.reference : b.weights_reference) game_of[d] = int(g);
    }
    std::map<std::string, std::string> parent_of;
    for (const auto& b : a.default_rig.bones) parent_of[b.name] = b.parent;
    auto resolve = [&](std::string bone) {
        while (!bone.empty()) {
            const auto it = game_of.find(bone);
            if (it != game_of.end()) return it->second;
            bone = parent_of.count(bone) ? parent_of[bone] : "";
        }
        return 0;  // unreachable for the shipped rigs: the root is listed
    };
    std::vector<std::map<int, double>> acc(mh::kBodyVertices);
    for (const auto& [bone, list] : a.default_weights) {
        const int g = resolve(bone);
        for (const auto& [v, w] : list)
            if (v < mh::kBodyVertices) acc[v][g] += w;
    }
    joints.assign(4ull * mh::kBodyVertices, 0);
    weights.assign(4ull * mh::kBodyVertices, 0.f);
    for (uint32_t v = 0; v < mh::kBodyVertices; ++v) {
        std::vector<std::pair<double, int>> top;
        for (const auto& [g, w] : acc[v]) top.emplace_back(w, g);
        std::sort(top.rbegin(), top.rend());
        if (top.size() > 4) top.resize(4);
        double sum = 0;
        for (const auto& t : top) sum += t.first;
        if (top.empty() || sum <= 0) {  // an unweighted vertex follows the pelvis-level root
            weights[4 * v] = 1.f;
            continue;
        }
        for (std::size_t i = 0; i < top.size(); ++i) {
            joints[4 * v + i] = uint16_t(top[i].second);
            weights[4 * v + i] = float(top[i].first / sum);
        }
    }
}

std::vector<float> game_rest_orientations(const mh::Assets& a, const std::vector<float>& xyz) {
    const auto& bones = a.game_rig.bones;
    std::map<std::string, int> index;
    for (std::size_t i = 0; i < bones.size(); ++i) index[bones[i].name] = int(i);
    std::vector<Eigen::Quaterniond> world(bones.size());
    std::vector<float> out;
    for (std::size_t i = 0; i < bones.size(); ++i) {
        const Eigen::Vector3d head = joint_position(a, a.game_rig, bones[i].head, xyz);
        const Eigen::Vector3d tail = joint_position(a, a.game_rig, bones[i].tail, xyz);
        const Eigen::Vector3d dir = (tail - head).normalized();
        world[i] = Eigen::AngleAxisd(bones[i].roll, dir) * Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), dir);
        const Eigen::Quaterniond local =
            bones[i].parent.empty() ? world[i] : world[std::size_t(index.at(bones[i].parent))].conjugate() * world[i];
        out.insert(out.end(), {float(local.x()), float(local.y()), float(local.z()), float(local.w())});
    }
    return out;
}

std::vector<float> apply_regressor(const uint32_t* offsets, const uint32_t* vertices, const float* weights, std::size_t joints,
                                   const float* xyz) {
    std::vector<float> out(3 * joints, 0.f);
    for (std::size_t j = 0; j < joints; ++j)
        for (uint32_t e = offsets[j]; e < offsets[j + 1]; ++e)
            for (std::size_t c = 0; c < 3; ++c) out[3 * j + c] += weights[e] * xyz[3 * std::size_t(vertices[e]) + c];
    return out;
}

}  // namespace ssc::training
