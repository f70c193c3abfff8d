#include "fitting/posed_surface.hpp"

#include <algorithm>

namespace ssc::fitting {

void set_fit_shape(Body& body, const std::vector<double>& shape) {
    const Model& m = body.model();
    const std::size_t K = m.component_count();
    std::vector<float> whole(shape.begin(), shape.begin() + std::min(shape.size(), K));
    body.set_shape(whole.data(), uint32_t(whole.size()));
    if (m.segments().empty()) return;
    std::vector<float> seg(m.segment_coefficient_count(), 0.f);
    for (std::size_t i = 0; i < seg.size() && K + i < shape.size(); ++i) seg[i] = float(shape[K + i]);
    for (uint32_t g = 0; g < m.segments().size(); ++g) body.set_segment_shape(g, seg.data() + m.segments()[g].first, m.segments()[g].components);
}

void posed_surface(Body& body, const FitState& s, std::vector<Vector3d>& vertices, std::vector<Vector3d>* normals) {
    const Model& m = body.model();
    const uint32_t V = m.vertex_count(), J = m.joint_count();
    std::vector<float> quats(4 * std::size_t(J));
    for (uint32_t j = 0; j < J; ++j) {
        const Eigen::Quaterniond q = s.pose[j].normalized();
        quats[4 * j] = float(q.x()), quats[4 * j + 1] = float(q.y()), quats[4 * j + 2] = float(q.z()), quats[4 * j + 3] = float(q.w());
    }
    set_fit_shape(body, s.shape);
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
