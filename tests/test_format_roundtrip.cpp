// A small model built in code is written and read back; every field must come back equal.
#include "support.hpp"

#include "common/error.hpp"
#include "sscape_format/basis_codec.hpp"
#include "sscape_format/container.hpp"
#include "sscape_format/model_io.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <random>

using namespace ssc;

template <class A, class B>
static void same(const A& a, const B& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) REQUIRE(a[i] == b[i]);
}

TEST_CASE("a model written and read back has every field equal", "[format]") {
    auto built = test::mini_model(true);
    format::ModelData& m = built.data;
    format::JointLimit limit;
    limit.joint = 2;
    const float c = std::cos(0.3f), s = std::sin(0.3f);
    const float frame[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    std::copy(frame, frame + 9, limit.frame);
    limit.lower[0] = -0.5f, limit.upper[0] = 2.f, limit.lower[2] = -0.1f, limit.upper[2] = 0.4f;
    m.joint_limits = {limit};
    // Roles: root, pelvis, spine, head, arm_l, arm_r (a left arm of one joint has no limb joints).
    m.joint_roles.assign(m.joint_count(), format::JointRole{});
    m.joint_roles[3] = {1, 0, 0.25, true, 0};
    m.joint_roles[4] = {2, 1, 0.6, true, 0};
    m.joint_roles[5] = {2, 2, 0.123456789012345, false, 0};
    m.attributes.attributes = {{"stature", "m", "height", 1.7f, 1.5f, 1.9f, true}, {"age", "years", "age", 40, 18, 80, false}};
    m.attributes.covariance = {0.01f, 0.02f, 0.02f, 300.f};
    for (uint32_t k = 0; k < 2 * m.component_count(); ++k) m.attributes.shape_covariance.push_back(0.01f * float(k));
    const auto bytes = format::write_model(m);
    const format::ModelData r = format::read_model(bytes.data(), bytes.size());

    CHECK(r.metadata.name == m.metadata.name);
    CHECK(r.metadata.model_version == m.metadata.model_version);
    CHECK(r.metadata.units == "m");
    CHECK(r.metadata.axes == m.metadata.axes);
    CHECK(r.metadata.license == m.metadata.license);
    CHECK(r.metadata.provenance == m.metadata.provenance);
    CHECK(r.metadata.description == m.metadata.description);

    CHECK(r.mesh.vertex_count == m.mesh.vertex_count);
    same(r.mesh.triangles, m.mesh.triangles);
    same(r.mesh.quads, m.mesh.quads);
    same(r.mesh.uvs, m.mesh.uvs);
    same(r.mesh.triangle_uvs, m.mesh.triangle_uvs);
    same(r.mesh.quad_uvs, m.mesh.quad_uvs);

    same(r.shape.mean, m.shape.mean);
    same(r.shape.stddev, m.shape.stddev);
    CHECK(r.shape.basis.components == m.shape.basis.components);
    same(r.shape.basis.step, m.shape.basis.step);
    same(r.shape.basis.q, m.shape.basis.q);

    same(r.skeleton.joint_names, m.skeleton.joint_names);
    same(r.skeleton.parents, m.skeleton.parents);
    same(r.skeleton.rest_orientations, m.skeleton.rest_orientations);
    same(r.skeleton.regressor_offsets, m.skeleton.regressor_offsets);
    same(r.skeleton.regressor_vertices, m.skeleton.regressor_vertices);
    same(r.skeleton.regressor_weights, m.skeleton.regressor_weights);

    same(r.skin.joints, m.skin.joints);
    same(r.skin.weights, m.skin.weights);

    REQUIRE(r.landmarks.size() == m.landmarks.size());
    for (std::size_t i = 0; i < m.landmarks.size(); ++i) {
        CHECK(r.landmarks[i].name == m.landmarks[i].name);
        CHECK(r.landmarks[i].vertex == m.landmarks[i].vertex);
        CHECK(r.landmarks[i].triangle == m.landmarks[i].triangle);
        for (int c = 0; c < 3; ++c) CHECK(r.landmarks[i].barycentric[c] == m.landmarks[i].barycentric[c]);
    }
    REQUIRE(r.vertex_sets.size() == m.vertex_sets.size());
    for (std::size_t i = 0; i < m.vertex_sets.size(); ++i) {
        CHECK(r.vertex_sets[i].name == m.vertex_sets[i].name);
        same(r.vertex_sets[i].vertices, m.vertex_sets[i].vertices);
    }
    REQUIRE(r.joint_limits.size() == 1);
    CHECK(r.joint_limits[0].joint == 2);
    for (int i = 0; i < 9; ++i) CHECK(r.joint_limits[0].frame[i] == limit.frame[i]);
    for (int i = 0; i < 3; ++i) CHECK((r.joint_limits[0].lower[i] == limit.lower[i] && r.joint_limits[0].upper[i] == limit.upper[i]));
    REQUIRE(r.joint_roles.size() == m.joint_roles.size());
    for (std::size_t j = 0; j < r.joint_roles.size(); ++j) {
        const format::JointRole &a = r.joint_roles[j], &b = m.joint_roles[j];
        CHECK((a.part == b.part && a.side == b.side && a.rotation_sigma == b.rotation_sigma && a.coarse == b.coarse &&
               a.limb_joint == b.limb_joint));
    }
    REQUIRE(r.attributes.attributes.size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        const auto &a = r.attributes.attributes[i], &b = m.attributes.attributes[i];
        CHECK((a.name == b.name && a.unit == b.unit && a.description == b.description && a.slider == b.slider));
        CHECK((a.mean == b.mean && a.minimum == b.minimum && a.maximum == b.maximum));
    }
    same(r.attributes.covariance, m.attributes.covariance);
    same(r.attributes.shape_covariance, m.attributes.shape_covariance);
}

TEST_CASE("quantization error stays within the requested tolerance", "[format]") {
    const auto built = test::mini_model();
    const auto& b = built.data.shape.basis;
    const double bound = format::quantization_error_bound(built.basis_float.data(), b, built.data.vertex_count());
    CHECK(bound <= 1e-4);
    CHECK(bound == Approx(built.quantization.max_error));
    // Direct check of the definition on every vertex, all components at +3 SD and at alternating signs.
    const uint32_t V = built.data.vertex_count();
    const std::size_t rows = 3ull * V;
    for (int pattern = 0; pattern < 2; ++pattern) {
        for (uint32_t v = 0; v < V; ++v) {
            double e[3] = {0, 0, 0};
            for (uint32_t k = 0; k < b.components; ++k) {
                const double c = (pattern == 0 || k % 2 == 0) ? 3.0 : -3.0;
                for (int a = 0; a < 3; ++a) {
                    const std::size_t i = k * rows + a * V + v;
                    e[a] += c * (built.basis_float[i] - double(b.step[k]) * b.q[i]);
                }
            }
            REQUIRE(std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) <= bound + 1e-12);
        }
    }
}

TEST_CASE("prediction tree covers every vertex once and predicts from earlier positions", "[format]") {
    const auto built = test::mini_model();
    const auto tree = format::build_prediction_tree(built.data.vertex_count(), built.data.mesh.triangles, built.data.mesh.quads);
    REQUIRE(tree.order.size() == built.data.vertex_count());
    std::vector<int> seen(built.data.vertex_count(), 0);
    for (std::size_t i = 0; i < tree.order.size(); ++i) {
        ++seen[tree.order[i]];
        REQUIRE(tree.predictor[i] <= i);
    }
    for (int s : seen) REQUIRE(s == 1);
}

TEST_CASE("a file written to disk loads through the C API", "[format][capi]") {
    const auto bytes = test::mini_bytes();
    const std::string path = "roundtrip_test.sscape";
    format::write_file(path, bytes);
    ssc_model* m = nullptr;
    REQUIRE(ssc_model_load_file(nullptr, path.c_str(), &m) == SSC_OK);
    CHECK(ssc_model_vertex_count(m) == 300);
    CHECK(ssc_model_joint_count(m) == 6);
    CHECK(ssc_model_shape_count(m) == 4);
    const char* s = nullptr;
    REQUIRE(ssc_model_get_metadata(m, SSC_METADATA_UNITS, &s) == SSC_OK);
    CHECK(std::string(s) == "m");
    ssc_model_release(m);
    std::remove(path.c_str());
    CHECK(ssc_model_load_file(nullptr, "no/such/file.sscape", &m) == SSC_ERROR_IO);
}

TEST_CASE("the default model is built in, verified, and what the README says", "[format][default]") {
    ssc_model* m = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &m) == SSC_OK);
    CHECK(ssc_model_vertex_count(m) == 13380);
    CHECK(ssc_model_joint_count(m) == 53);
    CHECK(ssc_model_shape_count(m) == 50);
    CHECK(ssc_model_landmark_count(m) == 73);
    uint32_t li = 0;
    CHECK(ssc_model_find_landmark(m, "Rt. Acromion", &li) == SSC_OK);
    const char* licence = nullptr;
    REQUIRE(ssc_model_get_metadata(m, SSC_METADATA_LICENSE, &licence) == SSC_OK);
    CHECK(std::string(licence).find("CC0") != std::string::npos);
    uint32_t j = 0;
    CHECK(ssc_model_find_joint(m, "lowerarm_l", &j) == SSC_OK);
    std::vector<float> sd(50);
    REQUIRE(ssc_model_get_shape_stddevs(m, sd.data(), 50) == SSC_OK);
    for (int k = 1; k < 50; ++k) CHECK(sd[k] <= sd[k - 1]);  // PCA order
    ssc_model_release(m);
}

TEST_CASE("mirror prediction codes the default model in far fewer bytes and decodes it exactly", "[format][default]") {
    const void* data = nullptr;
    std::size_t size = 0;
    REQUIRE(ssc_default_model_file(&data, &size) == SSC_OK);
    CHECK(ssc_default_model_file(nullptr, &size) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_default_model_file(&data, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    const auto* file = static_cast<const unsigned char*>(data);
    CHECK(size <= 2500000);  // issue 49: the model with its levels of detail within 2.5 MB
    CHECK((file[8] | file[9] << 8) == format::kContainerMajor);
    const format::ModelData d = format::read_model(file, size);
    const auto mirrored = format::write_model(d);
    format::WriteOptions plain;
    plain.mirror_prediction = false;
    const auto tree_only = format::write_model(d, plain);
    INFO(mirrored.size() << " bytes with mirror prediction, " << tree_only.size() << " without");
    CHECK(double(mirrored.size()) < 0.8 * double(tree_only.size()));
    CHECK((tree_only[8] | tree_only[9] << 8) == 1);  // readable by 1.x readers
    for (const auto* bytes : {&mirrored, &tree_only}) {
        const format::ModelData back = format::read_model(bytes->data(), bytes->size());
        same(back.shape.basis.q, d.shape.basis.q);
        REQUIRE(back.segments.size() == d.segments.size());
        for (std::size_t s = 0; s < d.segments.size(); ++s) same(back.segments[s].basis.q, d.segments[s].basis.q);
    }
    // Nearly every vertex of the body has its twin.
    const auto tree = format::build_mirror_tree(d.vertex_count(), d.mesh.triangles, d.mesh.quads, d.shape.mean.data(), 1e-3);
    std::size_t twins = 0;
    for (std::size_t i = 0; i < tree.mirror.size(); ++i) twins += tree.mirror[i] != i;
    CHECK(twins > d.vertex_count() * 45 / 100);
}

TEST_CASE("mirror prediction round-trips any basis over any valid tree", "[format]") {
    std::mt19937 rng(3);
    const uint32_t n = 200, K = 3;
    format::PredictionTree tree;
    for (uint32_t i = 0; i < n; ++i) {
        tree.order.push_back(i);
        tree.predictor.push_back(i == 0 ? 0 : uint32_t(rng() % i));
        tree.mirror.push_back(i > 1 && rng() % 2 ? uint32_t(rng() % i) : i);
    }
    std::shuffle(tree.order.begin(), tree.order.end(), rng);
    format::QuantizedBasis b;
    b.components = K;
    b.step.assign(K, 1e-5f);
    for (std::size_t i = 0; i < 3ull * K * n; ++i) b.q.push_back(int16_t(int(rng() % 65535) - 32767));
    const format::EncodedBasis coded = format::encode_basis(b, n, tree);
    REQUIRE(coded.signs.size() == K);
    Vec<int16_t> q;
    format::decode_residuals(coded.planes.data(), coded.planes.size(), n, K, tree.order.data(), tree.predictor.data(), tree.mirror.data(),
                             coded.signs.data(), q);
    same(q, b.q);
}

TEST_CASE("hostile mirror arrays are refused", "[format][corrupt]") {
    const uint32_t n = 4;
    const uint32_t order[] = {0, 1, 2, 3}, predictor[] = {0, 0, 1, 2};
    std::vector<uint8_t> planes(4 * 3 * n, 0);
    Vec<int16_t> q;
    const int8_t good_sign[] = {1}, bad_sign[] = {2};
    const uint32_t forward[] = {0, 1, 3, 3}, good[] = {0, 0, 1, 2};
    auto decode = [&](const uint32_t* mirror, const int8_t* signs, const uint32_t* pred) {
        format::decode_residuals(planes.data(), planes.size(), n, 1, order, pred, mirror, signs, q);
    };
    REQUIRE_NOTHROW(decode(good, good_sign, predictor));
    CHECK_THROWS_AS(decode(forward, good_sign, predictor), Error);
    CHECK_THROWS_AS(decode(good, bad_sign, predictor), Error);
    CHECK_THROWS_AS(decode(good, nullptr, predictor), Error);
    CHECK_THROWS_AS(decode(nullptr, good_sign, predictor), Error);
    const uint32_t rootless[] = {0, 1, 1, 2};  // position 1 has a twin but no parent
    CHECK_THROWS_AS(decode(good, good_sign, rootless), Error);
}
