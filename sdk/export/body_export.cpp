#include "export/body_export.hpp"

#include "common/error.hpp"
#include "export/gltf_writer.hpp"
#include "export/mesh_writers.hpp"

#include <algorithm>
#include <cctype>

namespace ssc::exporters {
namespace {

// Body::posed() and rest_planar() are planar (x block, y block, z block): interleaved xyz here.
std::vector<float> interleaved(const float* planar, uint32_t n) {
    std::vector<float> out(3 * std::size_t(n));
    for (uint32_t v = 0; v < n; ++v)
        for (uint32_t a = 0; a < 3; ++a) out[3 * std::size_t(v) + a] = planar[std::size_t(a) * n + v];
    return out;
}

// The model's triangles and UVs into a MeshView or a RiggedBody (the same fields in both).
template <class View>
void set_surface(View& view, const format::ModelData& d) {
    view.triangle_count = uint32_t(d.mesh.triangles.size() / 3);
    view.triangles = d.mesh.triangles.data();
    if (d.mesh.uvs.empty()) return;
    view.uv_count = uint32_t(d.mesh.uvs.size() / 2);
    view.uvs = d.mesh.uvs.data();
    view.triangle_uvs = d.mesh.triangle_uvs.data();
}

}  // namespace

BodyFormat format_of(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj") return BodyFormat::Obj;
    if (ext == ".ply") return BodyFormat::Ply;
    if (ext == ".glb") return BodyFormat::Glb;
    fail(SSC_ERROR_INVALID_ARGUMENT, "'" + path + "': the formats are .obj (Wavefront), .ply (Stanford) and .glb (binary glTF, rigged)");
}

void write_body(Body& body, const std::string& path, BodyFormat format) {
    const Model& model = body.model();
    const auto& d = model.data();
    const uint32_t V = model.vertex_count(), J = model.joint_count();
    if (format != BodyFormat::Glb) {
        const std::vector<float> positions = interleaved(body.posed(), V);
        MeshView mesh;
        mesh.vertex_count = V;
        mesh.positions = positions.data();
        mesh.normals = body.normals();
        set_surface(mesh, d);
        return format == BodyFormat::Obj ? write_obj(path, mesh) : write_ply(path, mesh);
    }
    // glTF: the bind pose is the body's shape at rest; its normals come from a rest-posed twin.
    Body rest(model, nullptr);
    rest.set_shape(body.shape(), model.component_count());
    for (uint32_t s = 0; s < model.segments().size(); ++s)
        rest.set_segment_shape(s, body.segment_shape(s), model.segments()[s].components);
    const std::vector<float> rest_positions = interleaved(body.rest_planar(), V);
    RiggedBody rb;
    rb.vertex_count = V;
    rb.rest_positions = rest_positions.data();
    rb.rest_normals = rest.normals();
    set_surface(rb, d);
    rb.joint_count = J;
    rb.parents = d.skeleton.parents.data();
    rb.joint_names = d.skeleton.joint_names;
    rb.joint_world = body.world();
    rb.inverse_bind = body.inverse_bind();
    rb.skin_joints = d.skin.joints.data();
    rb.skin_weights = d.skin.weights.data();
    rb.name = d.metadata.name.empty() ? "body" : d.metadata.name;
    write_glb(path, rb);
}

}  // namespace ssc::exporters
