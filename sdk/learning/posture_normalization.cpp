#include "learning/posture_normalization.hpp"

#include "common/error.hpp"
#include "fitting/posed_surface.hpp"
#include "synthesis/body.hpp"

#include <Eigen/LU>

#include <cmath>

namespace ssc::learning {

Posture posture_from_name(const std::string& name) {
    if (name == "none") return Posture::None;
    if (name == "skeleton") return Posture::Skeleton;
    if (name == "laplacian") return Posture::Laplacian;
    fail(SSC_ERROR_INVALID_ARGUMENT, "posture normalization '" + name + "' is unknown (none, skeleton, laplacian)");
}

const char* posture_name(Posture p) { return p == Posture::None ? "none" : p == Posture::Skeleton ? "skeleton" : "laplacian"; }

std::vector<Eigen::Vector3d> unpose_skeleton(const Model& model, const fitting::FitState& fit, const std::vector<Eigen::Vector3d>& posed) {
    const uint32_t V = model.vertex_count(), J = model.joint_count();
    SSC_REQUIRE_ARG_S(posed.size() == V, "unpose: " << posed.size() << " vertices, the model has " << V);
    SSC_REQUIRE_ARG_S(fit.pose.size() == J && fit.shape.size() <= model.component_count() + model.segment_coefficient_count(),
                      "unpose: the fit has " << fit.pose.size() << " joint rotations and " << fit.shape.size() << " shape values; the model has "
                                             << J << " joints and " << model.component_count() + model.segment_coefficient_count()
                                             << " shape coefficients");
    SSC_REQUIRE_ARG(std::isfinite(fit.scale) && fit.scale > 0 && fit.translation.allFinite(), "unpose: the fit's scale and translation must be finite");
    for (const auto& x : posed) SSC_REQUIRE_ARG(x.allFinite(), "unpose: a registered vertex is not finite");
    std::vector<float> quats(4 * std::size_t(J));
    for (uint32_t j = 0; j < J; ++j) {
        SSC_REQUIRE_ARG(fit.pose[j].coeffs().allFinite() && fit.pose[j].norm() > 0, "unpose: a joint rotation is not finite");
        const Eigen::Quaterniond q = fit.pose[j].normalized();
        quats[4 * j] = float(q.x()), quats[4 * j + 1] = float(q.y()), quats[4 * j + 2] = float(q.z()), quats[4 * j + 3] = float(q.w());
    }
    for (double c : fit.shape) SSC_REQUIRE_ARG(std::isfinite(c), "unpose: a shape value is not finite");
    Body body(model, nullptr);
    fitting::set_fit_shape(body, fit.shape);  // the whole body's and the segments' (the skeleton follows both)
    body.set_pose(quats.data(), nullptr);
    const kernels::SkinMatrix* skinning = body.skinning();
    const auto& skin = model.data().skin;
    std::vector<Eigen::Vector3d> rest(V);
    for (uint32_t v = 0; v < V; ++v) {
        Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
        for (int i = 0; i < 4; ++i) {
            const float w = skin.weights[4 * std::size_t(v) + std::size_t(i)];
            if (w != 0) M += double(w) * Eigen::Map<const Eigen::Matrix4f>(skinning[skin.joints[4 * std::size_t(v) + std::size_t(i)]].m).cast<double>();
        }
        // posed = scale * (A u + b) + translation
        const Eigen::Vector3d y = (posed[v] - fit.translation) / fit.scale - M.block<3, 1>(0, 3);
        const Eigen::Matrix3d A = M.block<3, 3>(0, 0);
        // Blended rotations far apart (a joint bent by nearly 180 degrees) leave no inverse.
        SSC_REQUIRE_ARG_S(std::abs(A.determinant()) > 1e-6, "unpose: vertex " << v << "'s skinning transform cannot be inverted (the pose folds it)");
        rest[v] = A.partialPivLu().solve(y);
    }
    return rest;
}

}  // namespace ssc::learning
