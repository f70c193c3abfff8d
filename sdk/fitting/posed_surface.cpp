#include "fitting/posed_surface.hpp"

namespace ssc::fitting {

void posed_surface(Body& body, const FitState& s, std::vector<Vector3d>& vertices, std::vector<Vector3d>* normals) {
    const Model& m = body.model();
    const uint32_t V = m.vertex_count(), J = m.joint_count();
    std::vector<float> shape(s.shape.begin(), s.shape.begin() + std::min<std::size_t>(s.shape.size(), m.component_count()));
    std::vector<float> quats(4 * std::size_t(J));
    for (uint32_t j = 0; j < J; ++j) {
        const Eigen::Quaterniond q = s.pose[j].normalized();
        quats[4 * j] = float(q.x()), quats[4 * j + 1] = float(q.y()), quats[4 * j + 2] = float(q.z()), quats[4 * j + 3] = float(q.w());
    }
    body.set_shape(shape.data(), uint32_t(shape.size()));
    body.set_pose(quats.data(), nullptr);
    const float* p = body.posed();
    vertices.resize(V);
    for (uint32_t v = 0; v < V; ++v) vertices[v] = s.scale * Vector3d(p[v], p[V + v], p[2 * std::size_t(V) + v]) + s.translation;
    if (!normals) return;
    const float* n = body.normals();
    normals->resize(V);
    for (uint32_t v = 0; v < V; ++v) (*normals)[v] = Vector3d(n[3 * v], n[3 * v + 1], n[3 * v + 2]);
}

}  // namespace ssc::fitting
