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

// A twin of the body at rest (no pose): its whole-body shape plus extra (K, or null), its segments'.
void copy_shape(Body& to, const Body& from, const float* extra) {
    const Model& model = from.model();
    std::vector<float> c(from.shape(), from.shape() + model.component_count());
    if (extra)
        for (std::size_t k = 0; k < c.size(); ++k) c[k] += extra[k];
    to.set_shape(c.data(), model.component_count());
    for (uint32_t s = 0; s < model.segments().size(); ++s)
        to.set_segment_shape(s, from.segment_shape(s), model.segments()[s].components);
}

std::vector<float> difference(const float* a, const float* b, std::size_t n) {
    std::vector<float> d(n);
    for (std::size_t i = 0; i < n; ++i) d[i] = a[i] - b[i];
    return d;
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

void write_body(Body& body, const std::string& path, BodyFormat format, const ExportOptions& options) {
    const Model& model = body.model();
    const auto& d = model.data();
    const uint32_t level = options.level;
    const bool all = level == kAllLevels;
    SSC_REQUIRE_ARG_S(all || level <= model.level_count(), "level " << level << " of a model with " << model.level_count() + 1 << " levels (0 the full mesh)");
    SSC_REQUIRE_ARG(!all || format == BodyFormat::Glb, "every level in one file: glTF (.glb) only, one node per level");
    SSC_REQUIRE_ARG(options.morphs.empty() || format == BodyFormat::Glb, "morph targets: glTF (.glb) only");
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
    // glTF: the bind pose is the body's shape at rest; its normals come from a rest-posed twin, and
    // each morph target is a second twin's difference from it (the shape is linear in the
    // coefficients; normals to first order). Every level (kAllLevels) or the one asked for, on the
    // one skeleton.
    Body rest(model, nullptr), moved(model, nullptr);
    copy_shape(rest, body, nullptr);
    const uint32_t first = all ? 0 : level, last = all ? model.level_count() : level;
    std::vector<std::vector<float>> arrays;  // every array the meshes point into
    arrays.reserve((last - first + 1) * (1 + 2 * options.morphs.size()));
    RiggedBody rb;
    const std::string name = d.metadata.name.empty() ? "body" : d.metadata.name;
    for (uint32_t l = first; l <= last; ++l) {
        RiggedMesh mesh;
        mesh.name = name;
        mesh.vertex_count = model.level_mesh(l).vertex_count;
        arrays.push_back(interleaved(l ? body.level_rest(l - 1) : body.rest_planar(), mesh.vertex_count));
        mesh.rest_positions = arrays.back().data();
        mesh.rest_normals = l ? rest.level_normals(l - 1) : rest.normals();
        const Model::LevelMesh lm = model.level_mesh(l);
        set_surface(mesh, lm);
        mesh.skin_joints = lm.skin_joints;
        mesh.skin_weights = lm.skin_weights;
        rb.meshes.push_back(mesh);
    }
    for (const MorphTarget& m : options.morphs) {
        SSC_REQUIRE_ARG(m.coefficients.size() == model.component_count(), "morph targets: one coefficient per component");
        copy_shape(moved, body, m.coefficients.data());
        for (uint32_t l = first; l <= last; ++l) {
            RiggedMesh& mesh = rb.meshes[l - first];
            const std::size_t n = 3ull * mesh.vertex_count;
            arrays.push_back(interleaved(l ? moved.level_rest(l - 1) : moved.rest_planar(), mesh.vertex_count));
            for (std::size_t i = 0; i < n; ++i) arrays.back()[i] -= mesh.rest_positions[i];
            mesh.morph_positions.push_back(arrays.back().data());
            arrays.push_back(difference(l ? moved.level_normals(l - 1) : moved.normals(), mesh.rest_normals, n));
            mesh.morph_normals.push_back(arrays.back().data());
        }
        rb.morphs.push_back({m.name, difference(moved.rest_joints(), rest.rest_joints(), 3ull * J), m.kind, m.unit, m.per_weight});
    }
    rb.joint_count = J;
    rb.parents = d.skeleton.parents.data();
    rb.joint_names = d.skeleton.joint_names;
    rb.joint_world = body.world();
    rb.inverse_bind = body.inverse_bind();
    write_glb(path, rb);
}

}  // namespace ssc::exporters
