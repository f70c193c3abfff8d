#include "export/body_export.hpp"

#include "common/error.hpp"
#include "export/gltf_writer.hpp"
#include "export/mesh_writers.hpp"

#include <algorithm>
#include <cctype>

namespace ssc::exporters {
namespace {

// Body::posed(), rest_planar() and the levels' are planar (x block, y block, z block): interleaved xyz here.
std::vector<float> interleaved(const float* planar, uint32_t n) {
    std::vector<float> out(3 * std::size_t(n));
    for (uint32_t v = 0; v < n; ++v)
        for (uint32_t a = 0; a < 3; ++a) out[3 * std::size_t(v) + a] = planar[std::size_t(a) * n + v];
    return out;
}

// A level's triangles and UVs (Model::level_mesh) into a MeshView or a RiggedMesh (the same
// fields in both).
template <class View>
void set_surface(View& view, const Model::LevelMesh& l) {
    view.triangle_count = l.triangle_count;
    view.triangles = l.triangles;
    view.uv_count = l.uv_count;
    view.uvs = l.uvs;
    view.triangle_uvs = l.triangle_uvs;
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

void write_body(Body& body, const std::string& path, BodyFormat format, uint32_t level) {
    const Model& model = body.model();
    const auto& d = model.data();
    const bool all = level == kAllLevels;
    SSC_REQUIRE_ARG_S(all || level <= model.level_count(), "level " << level << " of a model with " << model.level_count() + 1 << " levels (0 the full mesh)");
    SSC_REQUIRE_ARG(!all || format == BodyFormat::Glb, "every level in one file: glTF (.glb) only, one node per level");
    const uint32_t V = all ? 0 : model.level_mesh(level).vertex_count, J = model.joint_count();
    if (format != BodyFormat::Glb) {
        const std::vector<float> positions = interleaved(level ? body.level_posed(level - 1) : body.posed(), V);
        MeshView mesh;
        mesh.vertex_count = V;
        mesh.positions = positions.data();
        mesh.normals = level ? body.level_normals(level - 1) : body.normals();
        set_surface(mesh, model.level_mesh(level));
        return format == BodyFormat::Obj ? write_obj(path, mesh) : write_ply(path, mesh);
    }
    // glTF: the bind pose is the body's shape at rest; its normals come from a rest-posed twin.
    // Every level (kAllLevels) or the one asked for, on the one skeleton.
    Body rest(model, nullptr);
    rest.set_shape(body.shape(), model.component_count());
    for (uint32_t s = 0; s < model.segments().size(); ++s)
        rest.set_segment_shape(s, body.segment_shape(s), model.segments()[s].components);
    std::vector<std::vector<float>> rest_positions;
    RiggedBody rb;
    const std::string name = d.metadata.name.empty() ? "body" : d.metadata.name;
    for (uint32_t l = all ? 0 : level; l <= (all ? model.level_count() : level); ++l) {
        RiggedMesh mesh;
        mesh.name = name;
        mesh.vertex_count = model.level_mesh(l).vertex_count;
        rest_positions.push_back(interleaved(l ? body.level_rest(l - 1) : body.rest_planar(), mesh.vertex_count));
        mesh.rest_positions = rest_positions.back().data();
        mesh.rest_normals = l ? rest.level_normals(l - 1) : rest.normals();
        const Model::LevelMesh lm = model.level_mesh(l);
        set_surface(mesh, lm);
        mesh.skin_joints = lm.skin_joints;
        mesh.skin_weights = lm.skin_weights;
        rb.meshes.push_back(mesh);
    }
    rb.joint_count = J;
    rb.parents = d.skeleton.parents.data();
    rb.joint_names = d.skeleton.joint_names;
    rb.joint_world = body.world();
    rb.inverse_bind = body.inverse_bind();
    write_glb(path, rb);
}

}  // namespace ssc::exporters
