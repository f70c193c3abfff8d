#include "common/error.hpp"
#include "common/files.hpp"
#include "sscape_format/basis_codec.hpp"
#include "sscape_format/container.hpp"
#include "sscape_format/model_io.hpp"
#include "sscape_model_generated.h"

#include <cstring>

static_assert(FLATBUFFERS_LITTLEENDIAN, "the reader copies FlatBuffers vectors directly: little-endian hosts only");

namespace ssc::format {
namespace {

namespace fb = sscape::fb;

template <class T>
void copy(const flatbuffers::Vector<T>* v, Vec<T>& out) {
    if (!v) return;
    out.resize(v->size());
    if (v->size()) std::memcpy(out.data(), v->data(), v->size() * sizeof(T));
}

template <class T>
const flatbuffers::Vector<T>* need(const flatbuffers::Vector<T>* v, const char* what) {
    SSC_REQUIRE_MODEL(v != nullptr, std::string(what) + " is missing");
    return v;
}

std::string text(const flatbuffers::String* s) { return s ? s->str() : std::string(); }

// A basis's optional mirror prediction arrays (container 2.0): both or neither, sized by positions
// and components. Returns null pointers without them.
std::pair<const uint32_t*, const int8_t*> mirror_arrays(const flatbuffers::Vector<uint32_t>* mirror, const flatbuffers::Vector<int8_t>* signs,
                                                         uint32_t n, uint32_t components, const std::string& what) {
    if (!mirror && !signs) return {nullptr, nullptr};
    SSC_REQUIRE_MODEL(mirror && signs && mirror->size() == n && signs->size() == components,
                      what + ": mirror needs one entry per position and mirror_signs one per component");
    return {mirror->data(), signs->data()};
}

}  // namespace

ModelData read_model(const void* data, std::size_t size, const ReadOptions& options) {
    SSC_REQUIRE_ARG(data != nullptr || size == 0, "data is NULL");
    const Allocator* a = options.allocator;
    ContentBuffer buffer{ContentAlloc(a)};
    unpack_container(data, size, options.max_model_bytes ? options.max_model_bytes : kDefaultMaxModelBytes, buffer);

    flatbuffers::Verifier verifier(buffer.data(), buffer.size());
    SSC_REQUIRE_MODEL(fb::ModelBufferHasIdentifier(buffer.data()), "FlatBuffers identifier is not \"SSCM\"");
    SSC_REQUIRE_MODEL(fb::VerifyModelBuffer(verifier), "FlatBuffers verification failed: the model buffer is malformed");
    const fb::Model* root = fb::GetModel(buffer.data());

    ModelData m;
    // Point every array at the context's allocator before anything is filled.
    auto bind = [&](auto& v) { v = std::decay_t<decltype(v)>(typename std::decay_t<decltype(v)>::allocator_type(a)); };
    bind(m.mesh.triangles); bind(m.mesh.quads); bind(m.mesh.uvs); bind(m.mesh.triangle_uvs); bind(m.mesh.quad_uvs);
    bind(m.shape.mean); bind(m.shape.stddev); bind(m.shape.basis.step); bind(m.shape.basis.q);
    bind(m.skeleton.parents); bind(m.skeleton.rest_orientations); bind(m.skeleton.regressor_offsets);
    bind(m.skeleton.regressor_vertices); bind(m.skeleton.regressor_weights);
    bind(m.skin.joints); bind(m.skin.weights);

    if (const auto* md = root->metadata()) {
        m.metadata.name = text(md->name());
        m.metadata.model_version = text(md->model_version());
        m.metadata.units = text(md->units());
        m.metadata.axes = text(md->axes());
        m.metadata.license = text(md->license());
        m.metadata.provenance = text(md->provenance());
        m.metadata.description = text(md->description());
    }

    const auto* mesh = root->mesh();
    SSC_REQUIRE_MODEL(mesh != nullptr, "mesh is missing");
    m.mesh.vertex_count = mesh->vertex_count();
    copy(need(mesh->triangles(), "mesh.triangles"), m.mesh.triangles);
    copy(mesh->quads(), m.mesh.quads);
    copy(mesh->uvs(), m.mesh.uvs);
    copy(mesh->triangle_uvs(), m.mesh.triangle_uvs);
    copy(mesh->quad_uvs(), m.mesh.quad_uvs);

    const auto* shape = root->shape();
    SSC_REQUIRE_MODEL(shape != nullptr, "shape is missing");
    copy(need(shape->mean(), "shape.mean"), m.shape.mean);
    copy(need(shape->stddev(), "shape.stddev"), m.shape.stddev);
    copy(need(shape->step(), "shape.step"), m.shape.basis.step);
    m.shape.basis.components = static_cast<uint32_t>(m.shape.stddev.size());
    const uint32_t V = m.mesh.vertex_count;
    SSC_REQUIRE_MODEL(m.shape.mean.size() == 3ull * V, "shape.mean does not hold 3 floats per vertex");
    const auto* order = need(shape->vertex_order(), "shape.vertex_order");
    const auto* pred = need(shape->predictor(), "shape.predictor");
    const auto* planes = need(shape->residual_planes(), "shape.residual_planes");
    SSC_REQUIRE_MODEL(order->size() == V && pred->size() == V, "shape.vertex_order/predictor must hold one entry per vertex");
    // Bounded: the plane size is checked against components * 3V before q is allocated.
    const auto [mirror, signs] = mirror_arrays(shape->mirror(), shape->mirror_signs(), V, m.shape.basis.components, "shape");
    decode_residuals(planes->data(), planes->size(), V, m.shape.basis.components, order->data(), pred->data(), mirror, signs,
                     m.shape.basis.q);

    const auto* sk = root->skeleton();
    SSC_REQUIRE_MODEL(sk != nullptr, "skeleton is missing");
    const auto* names = need(sk->joint_names(), "skeleton.joint_names");
    for (const auto* s : *names) m.skeleton.joint_names.push_back(text(s));
    copy(need(sk->parents(), "skeleton.parents"), m.skeleton.parents);
    copy(need(sk->rest_orientations(), "skeleton.rest_orientations"), m.skeleton.rest_orientations);
    copy(need(sk->regressor_offsets(), "skeleton.regressor_offsets"), m.skeleton.regressor_offsets);
    copy(need(sk->regressor_vertices(), "skeleton.regressor_vertices"), m.skeleton.regressor_vertices);
    copy(need(sk->regressor_weights(), "skeleton.regressor_weights"), m.skeleton.regressor_weights);

    const auto* skin = root->skin();
    SSC_REQUIRE_MODEL(skin != nullptr, "skin is missing");
    copy(need(skin->joints(), "skin.joints"), m.skin.joints);
    copy(need(skin->weights(), "skin.weights"), m.skin.weights);

    if (const auto* lms = root->landmarks()) {
        for (const auto* l : *lms) {
            Landmark out;
            out.name = text(l->name());
            out.vertex = l->vertex();
            out.triangle = l->triangle();
            if (const auto* b = l->barycentric()) {
                out.barycentric[0] = b->u();
                out.barycentric[1] = b->v();
                out.barycentric[2] = b->w();
            }
            m.landmarks.push_back(std::move(out));
        }
    }
    if (const auto* sets = root->vertex_sets()) {
        for (const auto* s : *sets) {
            VertexSet out;
            out.name = text(s->name());
            out.vertices = Vec<uint32_t>(CAlloc<uint32_t>(a));
            copy(s->vertices(), out.vertices);
            m.vertex_sets.push_back(std::move(out));
        }
    }

    if (const auto* limits = root->joint_limits()) {
        for (const auto* l : *limits) {
            JointLimit out;
            out.joint = l->joint();
            const auto* frame = need(l->frame(), "joint_limits.frame");
            const auto* lower = need(l->lower(), "joint_limits.lower");
            const auto* upper = need(l->upper(), "joint_limits.upper");
            SSC_REQUIRE_MODEL(frame->size() == 9 && lower->size() == 3 && upper->size() == 3,
                              "joint limit " + std::to_string(m.joint_limits.size()) + " needs 9 frame and 3 + 3 bound values");
            std::copy(frame->begin(), frame->end(), out.frame);
            std::copy(lower->begin(), lower->end(), out.lower);
            std::copy(upper->begin(), upper->end(), out.upper);
            m.joint_limits.push_back(out);
        }
    }
    if (const auto* am = root->attributes()) {
        for (const auto* at : *need(am->attributes(), "attributes.attributes")) {
            Attribute out;
            out.name = text(at->name());
            out.unit = text(at->unit());
            out.description = text(at->description());
            out.mean = at->mean();
            out.minimum = at->minimum();
            out.maximum = at->maximum();
            out.slider = at->slider();
            m.attributes.attributes.push_back(std::move(out));
        }
        // Sizes are checked against the attribute count before anything is copied.
        const auto* cov = need(am->covariance(), "attributes.covariance");
        const auto* shape_cov = need(am->shape_covariance(), "attributes.shape_covariance");
        const std::size_t A = m.attributes.attributes.size();
        SSC_REQUIRE_MODEL(cov->size() == A * A, "attributes.covariance must hold A x A values");
        SSC_REQUIRE_MODEL(shape_cov->size() == A * m.shape.basis.components, "attributes.shape_covariance must hold A x K values");
        m.attributes.covariance.assign(cov->begin(), cov->end());
        m.attributes.shape_covariance.assign(shape_cov->begin(), shape_cov->end());
    }
    if (const auto* roles = root->joint_roles()) {
        for (const auto* r : *roles) {
            JointRole out;
            out.part = r->part();
            out.side = r->side();
            out.rotation_sigma = r->rotation_sigma();
            out.coarse = r->coarse();
            out.limb_joint = r->limb_joint();
            m.joint_roles.push_back(out);
        }
    }

    if (const auto* segments = root->segments()) {
        for (const auto* sg : *segments) {
            ShapeSegment out;
            out.name = text(sg->name());
            const auto* vertices = need(sg->vertices(), "segments.vertices");
            out.vertices.assign(vertices->begin(), vertices->end());
            const auto* weights = need(sg->weights(), "segments.weights");
            out.weights.assign(weights->begin(), weights->end());
            const auto* stddev = need(sg->stddev(), "segments.stddev");
            out.stddev.assign(stddev->begin(), stddev->end());
            out.basis.step = Vec<float>(CAlloc<float>(a));
            out.basis.q = Vec<int16_t>(CAlloc<int16_t>(a));
            copy(need(sg->step(), "segments.step"), out.basis.step);
            out.basis.components = static_cast<uint32_t>(out.stddev.size());
            const auto n = static_cast<uint32_t>(out.vertices.size());
            const auto* order = need(sg->vertex_order(), "segments.vertex_order");
            const auto* pred = need(sg->predictor(), "segments.predictor");
            const auto* planes = need(sg->residual_planes(), "segments.residual_planes");
            SSC_REQUIRE_MODEL(order->size() == n && pred->size() == n,
                              "segment '" + out.name + "': vertex_order/predictor must hold one entry per segment vertex");
            const auto [mirror, signs] = mirror_arrays(sg->mirror(), sg->mirror_signs(), n, out.basis.components, "segment '" + out.name + "'");
            decode_residuals(planes->data(), planes->size(), n, out.basis.components, order->data(), pred->data(), mirror, signs,
                             out.basis.q);
            m.segments.push_back(std::move(out));
        }
    }

    if (const auto* levels = root->levels()) {
        for (const auto* lv : *levels) {
            DetailLevel out;
            out.name = text(lv->name());
            out.vertex_count = lv->vertex_count();
            const std::string what = "level '" + out.name + "'";
            auto take = [&](const auto* v, auto& into, const char* field) {
                SSC_REQUIRE_MODEL(v != nullptr, what + ": " + field + " is missing");
                into.assign(v->begin(), v->end());
            };
            take(lv->sources(), out.sources, "sources");
            take(lv->source_weights(), out.source_weights, "source_weights");
            take(lv->triangles(), out.triangles, "triangles");
            if (lv->uvs()) take(lv->uvs(), out.uvs, "uvs");
            if (lv->triangle_uvs()) take(lv->triangle_uvs(), out.triangle_uvs, "triangle_uvs");
            take(lv->skin_joints(), out.skin_joints, "skin_joints");
            take(lv->skin_weights(), out.skin_weights, "skin_weights");
            take(lv->landmark_triangles(), out.landmark_triangles, "landmark_triangles");
            take(lv->landmark_barycentric(), out.landmark_barycentric, "landmark_barycentric");
            m.levels.push_back(std::move(out));
        }
    }

    validate_model(m);
    return m;
}

ModelData read_model_file(const std::string& path, const ReadOptions& options, std::string* digest) {
    // A container is at most header + a zstd bound of the content cap: larger files are refused unread.
    const uint64_t cap = options.max_model_bytes ? options.max_model_bytes : kDefaultMaxModelBytes;
    const std::string bytes = read_regular_file(path, kHeaderSize + cap + cap / 128 + (1 << 17), SSC_ERROR_MODEL_CORRUPT);
    if (digest) *digest = content_digest(bytes.data(), bytes.size());
    try {
        return read_model(bytes.data(), bytes.size(), options);
    } catch (const Error& e) {
        throw Error(e.status(), "'" + path + "': " + e.what());
    }
}

}  // namespace ssc::format
