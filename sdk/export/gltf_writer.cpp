#include "gltf_writer.hpp"

#include "common/files.hpp"
#include "common/error.hpp"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <map>

namespace ssc::exporters {
namespace {

using nlohmann::json;

struct Bin {
    std::vector<unsigned char> bytes;
    json views = json::array(), accessors = json::array();

    // Appends data as a buffer view (4-byte aligned) and an accessor over it; returns the accessor.
    int add(const void* data, std::size_t size, int component, std::size_t count, const char* type, int target,
            const json& extra = json::object()) {
        while (bytes.size() % 4) bytes.push_back(0);
        json view = {{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}};
        if (target) view["target"] = target;
        views.push_back(view);
        const auto* p = static_cast<const unsigned char*>(data);
        bytes.insert(bytes.end(), p, p + size);
        json acc = {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}};
        acc.update(extra);
        accessors.push_back(acc);
        return int(accessors.size() - 1);
    }
};

constexpr int kFloat = 5126, kUShort = 5123, kUInt = 5125;

// The skin material's base colour texture: one white pixel (PNG), so the colour is the factor's and
// the UVs are there for an engine's own skin texture to replace it.
constexpr unsigned char kWhitePixelPng[] = {
    0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,
    0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53, 0xDE, 0x00, 0x00, 0x00, 0x0C, 0x49, 0x44, 0x41, 0x54, 0x08, 0xD7, 0x63, 0xF8, 0xFF,
    0xFF, 0x3F, 0x00, 0x05, 0xFE, 0x02, 0xFE, 0xDC, 0xCC, 0x59, 0xE7, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};
constexpr int kArrayBuffer = 34962, kElementBuffer = 34963;

// One mesh's primitive: its attributes and indices in the binary chunk, one output vertex per
// distinct (vertex, uv) pair (glTF attributes are per vertex). Returns the primitive (material 0).
json add_primitive(Bin& bin, const RiggedMesh& b, uint32_t joint_count, std::size_t morph_count) {
    SSC_REQUIRE_ARG(b.vertex_count > 0 && b.rest_positions && b.triangles && b.triangle_count > 0, "glTF export: no mesh");
    SSC_REQUIRE_ARG(b.skin_joints && b.skin_weights, "glTF export: a mesh without a skin");
    const bool has_uv = b.uvs && b.triangle_uvs && b.uv_count > 0;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> remap;
    std::vector<uint32_t> source, indices(3ull * b.triangle_count);
    std::vector<uint32_t> uv_of;
    for (std::size_t c = 0; c < indices.size(); ++c) {
        const uint32_t v = b.triangles[c], t = has_uv ? b.triangle_uvs[c] : 0;
        SSC_REQUIRE_ARG(v < b.vertex_count && (!has_uv || t < b.uv_count), "glTF export: index out of range");
        const auto [it, added] = remap.emplace(std::make_pair(v, t), uint32_t(source.size()));
        if (added) {
            source.push_back(v);
            uv_of.push_back(t);
        }
        indices[c] = it->second;
    }
    const std::size_t n = source.size();
    std::vector<float> pos(3 * n), nrm(3 * n), uv(2 * n), weights(4 * n);
    std::vector<uint16_t> joints(4 * n);
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t v = source[i];
        for (int a = 0; a < 3; ++a) {
            pos[3 * i + a] = b.rest_positions[3 * v + a];
            lo[a] = std::min(lo[a], pos[3 * i + a]);
            hi[a] = std::max(hi[a], pos[3 * i + a]);
            if (b.rest_normals) nrm[3 * i + a] = b.rest_normals[3 * v + a];
        }
        if (has_uv) {
            uv[2 * i] = b.uvs[2 * uv_of[i]];
            uv[2 * i + 1] = 1.f - b.uvs[2 * uv_of[i] + 1];  // glTF's v points down
        }
        for (int k = 0; k < 4; ++k) {
            SSC_REQUIRE_ARG(b.skin_joints[4 * v + k] < joint_count, "glTF export: a skin joint out of range");
            // glTF wants unused influences as joint 0 with weight 0.
            joints[4 * i + k] = b.skin_weights[4 * v + k] > 0 ? b.skin_joints[4 * v + k] : 0;
            weights[4 * i + k] = b.skin_weights[4 * v + k];
        }
    }
    json attributes;
    attributes["POSITION"] = bin.add(pos.data(), pos.size() * 4, kFloat, n, "VEC3", kArrayBuffer,
                                     {{"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}});
    if (b.rest_normals) attributes["NORMAL"] = bin.add(nrm.data(), nrm.size() * 4, kFloat, n, "VEC3", kArrayBuffer);
    if (has_uv) attributes["TEXCOORD_0"] = bin.add(uv.data(), uv.size() * 4, kFloat, n, "VEC2", kArrayBuffer);
    attributes["JOINTS_0"] = bin.add(joints.data(), joints.size() * 2, kUShort, n, "VEC4", kArrayBuffer);
    attributes["WEIGHTS_0"] = bin.add(weights.data(), weights.size() * 4, kFloat, n, "VEC4", kArrayBuffer);
    // The mesh vertex each glTF vertex was split from (glTF allows no integer vertex attributes).
    std::vector<float> model_vertex(source.begin(), source.end());
    attributes["_MODEL_VERTEX"] = bin.add(model_vertex.data(), n * 4, kFloat, n, "SCALAR", kArrayBuffer);
    const int index_acc = bin.add(indices.data(), indices.size() * 4, kUInt, indices.size(), "SCALAR", kElementBuffer);
    json primitive = {{"attributes", attributes}, {"indices", index_acc}, {"mode", 4}, {"material", 0}};

    SSC_REQUIRE_ARG(b.morph_positions.size() == morph_count && (b.morph_normals.empty() || b.morph_normals.size() == morph_count),
                    "glTF export: a mesh without every morph target");
    json targets = json::array();
    std::vector<float> delta(3 * n);
    for (std::size_t m = 0; m < morph_count; ++m) {
        json target;
        float dlo[3] = {1e30f, 1e30f, 1e30f}, dhi[3] = {-1e30f, -1e30f, -1e30f};
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < 3; ++a) {
                delta[3 * i + a] = b.morph_positions[m][3 * source[i] + a];
                dlo[a] = std::min(dlo[a], delta[3 * i + a]);
                dhi[a] = std::max(dhi[a], delta[3 * i + a]);
            }
        target["POSITION"] = bin.add(delta.data(), delta.size() * 4, kFloat, n, "VEC3", kArrayBuffer,
                                     {{"min", {dlo[0], dlo[1], dlo[2]}}, {"max", {dhi[0], dhi[1], dhi[2]}}});
        if (!b.morph_normals.empty() && b.rest_normals) {
            for (std::size_t i = 0; i < n; ++i)
                for (int a = 0; a < 3; ++a) delta[3 * i + a] = b.morph_normals[m][3 * source[i] + a];
            target["NORMAL"] = bin.add(delta.data(), delta.size() * 4, kFloat, n, "VEC3", kArrayBuffer);
        }
        targets.push_back(target);
    }
    if (morph_count) primitive["targets"] = targets;
    return primitive;
}

// skins[0].extras.sscape_morphs: per morph target, what one unit of weight adds to each joint
// node's translation (node j's is its offset from its parent in the parent's rest frame,
// W_parent^T (p_j - p_parent), or p_root) and to each inverse bind matrix's translation (-W_j^T p_j).
json morph_joint_extras(const RiggedBody& b) {
    json out = json::array();
    for (const RiggedMorph& m : b.morphs) {
        SSC_REQUIRE_ARG(m.joint_offsets.size() == 3ull * b.joint_count, "glTF export: a morph target without its joints' offsets");
        std::vector<float> node(3ull * b.joint_count), ibm(3ull * b.joint_count);
        for (uint32_t j = 0; j < b.joint_count; ++j) {
            // The rest rotation W_j^T is the inverse bind matrix's upper-left 3x3.
            const Eigen::Matrix3f Wt = Eigen::Map<const Eigen::Matrix4f>(b.inverse_bind + 16 * j).topLeftCorner<3, 3>();
            const Eigen::Vector3f d(m.joint_offsets.data() + 3 * j);
            Eigen::Vector3f local = d;
            if (b.parents[j] >= 0) {
                const auto p = std::size_t(b.parents[j]);
                const Eigen::Matrix3f Wpt = Eigen::Map<const Eigen::Matrix4f>(b.inverse_bind + 16 * p).topLeftCorner<3, 3>();
                local = Wpt * (d - Eigen::Vector3f(m.joint_offsets.data() + 3 * p));
            }
            const Eigen::Vector3f bind = -(Wt * d);
            for (int a = 0; a < 3; ++a) node[3 * j + a] = local[a], ibm[3 * j + a] = bind[a];
        }
        out.push_back({{"name", m.name}, {"kind", m.kind}, {"per_weight", m.per_weight}, {"unit", m.unit},
                       {"node_translation", node}, {"inverse_bind_translation", ibm}, {"joint_position", m.joint_offsets}});
    }
    return out;
}

}  // namespace

void write_glb(const std::string& path, const RiggedBody& b) {
    SSC_REQUIRE_ARG(!b.meshes.empty(), "glTF export: no mesh");
    SSC_REQUIRE_ARG(b.joint_count > 0 && b.parents && b.joint_world && b.inverse_bind && b.joint_names.size() == b.joint_count,
                    "glTF export: incomplete skeleton");
    Bin bin;
    json meshes = json::array();
    json target_names = json::array();
    for (const RiggedMorph& m : b.morphs) target_names.push_back(m.name);
    for (const RiggedMesh& m : b.meshes) {
        json mesh = {{"name", m.name}, {"primitives", {add_primitive(bin, m, b.joint_count, b.morphs.size())}}};
        if (!b.morphs.empty()) {
            mesh["weights"] = std::vector<float>(b.morphs.size(), 0.f);
            mesh["extras"] = {{"targetNames", target_names}};
        }
        meshes.push_back(mesh);
    }
    const int ibm_acc = bin.add(b.inverse_bind, 64ull * b.joint_count, kFloat, b.joint_count, "MAT4", 0);

    // Joint nodes carry the posed local transforms: local = world_parent^-1 * world.
    json nodes = json::array();
    std::vector<json> children(b.joint_count, json::array());
    for (uint32_t j = 0; j < b.joint_count; ++j) {
        const Eigen::Matrix4f G = Eigen::Map<const Eigen::Matrix4f>(b.joint_world + 16 * j);
        Eigen::Matrix4f L = G;
        if (b.parents[j] >= 0) {
            SSC_REQUIRE_ARG(uint32_t(b.parents[j]) < j, "glTF export: parents must precede children");
            L = Eigen::Map<const Eigen::Matrix4f>(b.joint_world + 16 * b.parents[j]).inverse() * G;
            children[b.parents[j]].push_back(j);
        }
        const Eigen::Quaternionf q(Eigen::Matrix3f(L.topLeftCorner<3, 3>()));
        const Eigen::Quaternionf qn = q.normalized();
        json node = {{"name", b.joint_names[j]},
                     {"translation", {L(0, 3), L(1, 3), L(2, 3)}},
                     {"rotation", {qn.x(), qn.y(), qn.z(), qn.w()}}};
        nodes.push_back(node);
    }
    for (uint32_t j = 0; j < b.joint_count; ++j)
        if (!children[j].empty()) nodes[j]["children"] = children[j];
    std::vector<uint32_t> joint_list(b.joint_count);
    for (uint32_t j = 0; j < b.joint_count; ++j) joint_list[j] = j;
    // One node per mesh; with several (levels of detail) named NAME_LOD0, NAME_LOD1, ...
    json scene_nodes = json::array();
    for (std::size_t i = 0; i < b.meshes.size(); ++i) {
        const std::string name = b.meshes.size() == 1 ? b.meshes[i].name : b.meshes[i].name + "_LOD" + std::to_string(i);
        scene_nodes.push_back(nodes.size());
        nodes.push_back({{"name", name}, {"mesh", i}, {"skin", 0}});
    }
    for (uint32_t j = 0; j < b.joint_count; ++j)
        if (b.parents[j] < 0) scene_nodes.push_back(j);

    // A skin material: PBR, a neutral albedo, not metallic, fairly rough; its base colour texture
    // (one white pixel) uses the UVs where the mesh has them.
    bool any_uv = false;
    for (const RiggedMesh& m : b.meshes) any_uv |= m.uvs && m.uv_count > 0;
    json pbr = {{"baseColorFactor", {0.80, 0.62, 0.52, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.6}};
    json images = json::array(), textures = json::array(), samplers = json::array();
    if (any_uv) {
        while (bin.bytes.size() % 4) bin.bytes.push_back(0);
        bin.views.push_back({{"buffer", 0}, {"byteOffset", bin.bytes.size()}, {"byteLength", sizeof kWhitePixelPng}});
        bin.bytes.insert(bin.bytes.end(), kWhitePixelPng, kWhitePixelPng + sizeof kWhitePixelPng);
        images.push_back({{"bufferView", bin.views.size() - 1}, {"mimeType", "image/png"}});
        samplers.push_back({{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}});
        textures.push_back({{"source", 0}, {"sampler", 0}});
        pbr["baseColorTexture"] = {{"index", 0}};
    }
    json skin = {{"joints", joint_list}, {"inverseBindMatrices", ibm_acc}, {"skeleton", 0}};
    if (!b.morphs.empty()) skin["extras"] = {{"sscape_morphs", morph_joint_extras(b)}};
    const json material = {{"name", "skin"}, {"pbrMetallicRoughness", pbr}, {"doubleSided", false}};
    json doc = {{"asset", {{"version", "2.0"}, {"generator", "sscape"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", scene_nodes}}}},
                {"nodes", nodes},
                {"meshes", meshes},
                {"materials", {material}},
                {"skins", {skin}},
                {"buffers", {{{"byteLength", 0}}}},
                {"bufferViews", bin.views},
                {"accessors", bin.accessors}};
    if (any_uv) doc["images"] = images, doc["samplers"] = samplers, doc["textures"] = textures;
    while (bin.bytes.size() % 4) bin.bytes.push_back(0);
    doc["buffers"][0]["byteLength"] = bin.bytes.size();
    std::string text = doc.dump();
    while (text.size() % 4) text.push_back(' ');

    std::vector<unsigned char> out;
    auto u32 = [&](uint32_t v) { for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i))); };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + bin.bytes.size()));
    u32(uint32_t(text.size()));
    u32(0x4E4F534A);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    u32(uint32_t(bin.bytes.size()));
    u32(0x004E4942);  // "BIN\0"
    out.insert(out.end(), bin.bytes.begin(), bin.bytes.end());
    write_file_atomically(path, out.data(), out.size());
}

}  // namespace ssc::exporters
