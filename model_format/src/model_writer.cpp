#include "common/files.hpp"
#include "common/error.hpp"
#include "sscape_format/basis_codec.hpp"
#include "sscape_format/container.hpp"
#include "sscape_format/model_io.hpp"
#include "sscape_model_generated.h"


namespace ssc::format {
namespace {

template <class T>
flatbuffers::Offset<flatbuffers::Vector<T>> vec(flatbuffers::FlatBufferBuilder& fbb, const Vec<T>& v) {
    return fbb.CreateVector(v.data(), v.size());
}

// Optional arrays are left out of the buffer when empty.
template <class T>
flatbuffers::Offset<flatbuffers::Vector<T>> opt_vec(flatbuffers::FlatBufferBuilder& fbb, const Vec<T>& v) {
    return v.empty() ? 0 : vec(fbb, v);
}

// Vertices of the mean body within this of each other's mirror image are twins for mirror prediction.
constexpr double kMirrorTolerance = 1e-3;

// A segment's basis is predicted over the triangles whose corners all lie in the segment.
flatbuffers::Offset<sscape::fb::ShapeSegment> write_segment(flatbuffers::FlatBufferBuilder& fbb, const ShapeSegment& s,
                                                           const Mesh& mesh, const Vec<float>& mean, bool mirror) {
    const auto n = static_cast<uint32_t>(s.vertices.size());
    std::vector<uint32_t> local(mesh.vertex_count, kNone);
    for (uint32_t i = 0; i < n; ++i)
        if (s.vertices[i] < mesh.vertex_count) local[s.vertices[i]] = i;
    Vec<uint32_t> triangles;
    for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
        const uint32_t a = local[mesh.triangles[t]], b = local[mesh.triangles[t + 1]], c = local[mesh.triangles[t + 2]];
        if (a != kNone && b != kNone && c != kNone) triangles.insert(triangles.end(), {a, b, c});
    }
    std::vector<float> positions(3ull * n, 0.f);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t a = 0; a < 3 && 3ull * s.vertices[i] + a < mean.size(); ++a) positions[3 * i + a] = mean[3ull * s.vertices[i] + a];
    const PredictionTree tree = mirror ? build_mirror_tree(n, triangles, Vec<uint32_t>{}, positions.data(), kMirrorTolerance)
                                       : build_prediction_tree(n, triangles, Vec<uint32_t>{});
    const EncodedBasis coded = encode_basis(s.basis, n, tree);
    return sscape::fb::CreateShapeSegment(fbb, fbb.CreateString(s.name), fbb.CreateVector(s.vertices), fbb.CreateVector(s.weights),
                                          fbb.CreateVector(s.stddev), vec(fbb, s.basis.step), fbb.CreateVector(tree.order),
                                          fbb.CreateVector(tree.predictor), fbb.CreateVector(coded.planes),
                                          mirror ? fbb.CreateVector(tree.mirror) : 0, mirror ? fbb.CreateVector(coded.signs) : 0);
}

}  // namespace

std::vector<unsigned char> write_model(const ModelData& m, const WriteOptions& options) {
    if (options.validate) {
        try {
            validate_model(m);
        } catch (const Error& e) {
            fail(SSC_ERROR_INVALID_ARGUMENT, std::string("model to write is invalid: ") + e.what());
        }
    }
    namespace fb = sscape::fb;
    flatbuffers::FlatBufferBuilder fbb(1 << 20);
    auto str = [&](const std::string& s) { return fbb.CreateString(s); };

    const auto& md = m.metadata;
    auto meta = fb::CreateMetadata(fbb, str(md.name), str(md.model_version), str(md.units), str(md.axes),
                                   str(md.license), str(md.provenance), str(md.description));
    const auto& me = m.mesh;
    auto mesh = fb::CreateMesh(fbb, me.vertex_count, vec(fbb, me.triangles), opt_vec(fbb, me.quads),
                               opt_vec(fbb, me.uvs), opt_vec(fbb, me.triangle_uvs), opt_vec(fbb, me.quad_uvs));

    // Sized by the vertex data actually present (equal to vertex_count in any valid model).
    const auto data_vertices = static_cast<uint32_t>(m.shape.mean.size() / 3);
    const bool mirror = options.mirror_prediction;
    const PredictionTree tree = mirror ? build_mirror_tree(data_vertices, me.triangles, me.quads, m.shape.mean.data(), kMirrorTolerance)
                                       : build_prediction_tree(data_vertices, me.triangles, me.quads);
    const EncodedBasis coded = encode_basis(m.shape.basis, data_vertices, tree);
    auto shape = fb::CreateShapeSpace(fbb, vec(fbb, m.shape.mean), vec(fbb, m.shape.stddev), vec(fbb, m.shape.basis.step),
                                      fbb.CreateVector(tree.order), fbb.CreateVector(tree.predictor),
                                      fbb.CreateVector(coded.planes), mirror ? fbb.CreateVector(tree.mirror) : 0,
                                      mirror ? fbb.CreateVector(coded.signs) : 0);

    const auto& sk = m.skeleton;
    auto skeleton = fb::CreateSkeleton(fbb, fbb.CreateVectorOfStrings(sk.joint_names), vec(fbb, sk.parents),
                                       vec(fbb, sk.rest_orientations), vec(fbb, sk.regressor_offsets),
                                       vec(fbb, sk.regressor_vertices), vec(fbb, sk.regressor_weights));
    auto skin = fb::CreateSkin(fbb, vec(fbb, m.skin.joints), vec(fbb, m.skin.weights));

    std::vector<flatbuffers::Offset<fb::Landmark>> landmarks;
    for (const auto& l : m.landmarks) {
        const fb::Barycentric bary(l.barycentric[0], l.barycentric[1], l.barycentric[2]);
        landmarks.push_back(fb::CreateLandmark(fbb, str(l.name), l.vertex, l.triangle, &bary));
    }
    std::vector<flatbuffers::Offset<fb::VertexSet>> sets;
    for (const auto& s : m.vertex_sets) sets.push_back(fb::CreateVertexSet(fbb, str(s.name), vec(fbb, s.vertices)));

    std::vector<flatbuffers::Offset<fb::JointLimit>> limits;
    for (const auto& l : m.joint_limits)
        limits.push_back(fb::CreateJointLimit(fbb, l.joint, fbb.CreateVector(l.frame, 9), fbb.CreateVector(l.lower, 3),
                                              fbb.CreateVector(l.upper, 3)));
    flatbuffers::Offset<fb::AttributeModel> attributes = 0;
    if (!m.attributes.attributes.empty()) {
        std::vector<flatbuffers::Offset<fb::Attribute>> list;
        for (const auto& a : m.attributes.attributes)
            list.push_back(fb::CreateAttribute(fbb, str(a.name), str(a.unit), str(a.description), a.mean, a.minimum, a.maximum,
                                               a.slider));
        attributes = fb::CreateAttributeModel(fbb, fbb.CreateVector(list), fbb.CreateVector(m.attributes.covariance),
                                              fbb.CreateVector(m.attributes.shape_covariance));
    }

    std::vector<flatbuffers::Offset<fb::JointRole>> roles;
    for (const auto& r : m.joint_roles)
        roles.push_back(fb::CreateJointRole(fbb, r.part, r.side, r.rotation_sigma, r.coarse, r.limb_joint));

    std::vector<flatbuffers::Offset<fb::ShapeSegment>> segments;
    for (const auto& s : m.segments) segments.push_back(write_segment(fbb, s, me, m.shape.mean, mirror));

    std::vector<flatbuffers::Offset<fb::DetailLevel>> levels;
    for (const auto& l : m.levels)
        levels.push_back(fb::CreateDetailLevel(fbb, str(l.name), l.vertex_count, fbb.CreateVector(l.sources), fbb.CreateVector(l.source_weights),
                                               fbb.CreateVector(l.triangles), l.uvs.empty() ? 0 : fbb.CreateVector(l.uvs),
                                               l.uvs.empty() ? 0 : fbb.CreateVector(l.triangle_uvs), fbb.CreateVector(l.skin_joints),
                                               fbb.CreateVector(l.skin_weights), fbb.CreateVector(l.landmark_triangles),
                                               fbb.CreateVector(l.landmark_barycentric)));

    auto root = fb::CreateModel(fbb, meta, mesh, shape, skeleton, skin, fbb.CreateVector(landmarks),
                                fbb.CreateVector(sets), m.joint_limits.empty() ? 0 : fbb.CreateVector(limits), attributes,
                                m.joint_roles.empty() ? 0 : fbb.CreateVector(roles),
                                m.segments.empty() ? 0 : fbb.CreateVector(segments), m.levels.empty() ? 0 : fbb.CreateVector(levels));
    fb::FinishModelBuffer(fbb, root);
    return pack_container(fbb.GetBufferPointer(), fbb.GetSize(), options.zstd_level, mirror ? kContainerMajor : kOldestContainerMajor);
}

void write_file(const std::string& path, const std::vector<unsigned char>& bytes) {
    write_file_atomically(path, bytes.data(), bytes.size());
}

}  // namespace ssc::format
