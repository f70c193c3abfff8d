// Writes the fuzz targets' seed corpora, made by the project's own writers from a small procedural
// model (so the seeds are valid files of each kind, small enough to mutate quickly):
//   OUT/model_memory/   .sscape files          OUT/model_payload/  their FlatBuffers payloads
//   OUT/ply/            binary and ASCII PLY   OUT/obj/            OBJ with and without normals
//   OUT/lnd/            CAESAR .lnd            OUT/pgm/            16-bit PGM with camera comments
//   OUT/report/         registration reports   OUT/tables/         decisions and attributes CSV
//   OUT/params/         fit parameters
// usage: fuzz_seeds OUT
#include "export/mesh_writers.hpp"
#include "io/writers.hpp"
#include "sscape_format/container.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/body.hpp"
#include "synthesis/kernels.hpp"
#include "synthesis/model.hpp"
#include "testing/synthetic_model.hpp"

#include <sscape/sscape.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

void put(const fs::path& path, const void* data, std::size_t size) {
    std::ofstream(path, std::ios::binary).write(static_cast<const char*>(data), std::streamsize(size));
}
void put(const fs::path& path, const std::string& text) { put(path, text.data(), text.size()); }

ssc::testing::SyntheticModel small_model(ssc::testing::SyntheticSkeleton skeleton, uint32_t vertices, uint32_t components) {
    ssc::testing::SyntheticSpec spec;
    spec.skeleton = skeleton;
    spec.vertex_count = vertices;
    spec.components = components;
    spec.seed = 3;
    return ssc::testing::build_synthetic_model(spec);
}

// Two segment shape spaces over the vertices' halves, blended over a band between them, with
// two components each (the whole-body basis's first two, restricted): the segments field as a
// learned model has it, small.
void add_segments(ssc::format::ModelData& m) {
    const uint32_t V = m.vertex_count(), band = V / 10;
    for (int half = 0; half < 2; ++half) {
        ssc::format::ShapeSegment s;
        s.name = half ? "upper" : "lower";
        for (uint32_t v = 0; v < V; ++v) {
            const float t = std::clamp((float(v) - float(V / 2 - band / 2)) / float(band), 0.f, 1.f);  // 0 below the band, 1 above
            const float w = half ? t : 1.f - t;
            if (w > 0) s.vertices.push_back(v), s.weights.push_back(w);
        }
        const auto n = uint32_t(s.vertices.size());
        std::vector<float> basis(2ull * 3 * n);
        for (uint32_t k = 0; k < 2; ++k)
            for (uint32_t a = 0; a < 3; ++a)
                for (uint32_t i = 0; i < n; ++i)
                    basis[(k * 3 + a) * n + i] = s.weights[i] * m.shape.basis.step[k] * float(m.shape.basis.q[(std::size_t(k) * 3 + a) * V + s.vertices[i]]);
        s.stddev = {m.shape.stddev[0], m.shape.stddev[1]};
        s.basis = ssc::format::quantize_basis(basis.data(), n, 2, 1e-4);
        m.segments.push_back(std::move(s));
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT\n", argv[0]);
        return 2;
    }
    const fs::path out = argv[1];
    for (const char* d : {"model_memory", "model_payload", "ply", "obj", "lnd", "pgm", "report", "tables", "params"}) fs::create_directories(out / d);

    // Models: small meshes on the 6-joint skeleton (the humanoid one needs a full-size mesh).
    int n = 0;
    for (const auto& [skeleton, V, K, segments] : {std::tuple{ssc::testing::SyntheticSkeleton::Mini6, 300u, 4u, false},
                                                  std::tuple{ssc::testing::SyntheticSkeleton::Mini6, 600u, 6u, false},
                                                  std::tuple{ssc::testing::SyntheticSkeleton::Mini6, 300u, 4u, true}}) {
        auto model = small_model(skeleton, V, K);
        if (segments) add_segments(model.data);
        const std::vector<unsigned char> file = ssc::format::write_model(model.data);
        put(out / "model_memory" / ("model" + std::to_string(n) + ".sscape"), file.data(), file.size());
        ssc::format::ContentBuffer payload;
        ssc::format::unpack_container(file.data(), file.size(), ssc::format::kDefaultMaxModelBytes, payload);
        put(out / "model_payload" / ("payload" + std::to_string(n) + ".bin"), payload.data(), payload.size());
        ++n;
    }

    // A body of the small model as meshes and point clouds.
    const auto synthetic = small_model(ssc::testing::SyntheticSkeleton::Mini6, 300, 4);
    const ssc::Model model(synthetic.data, nullptr);
    ssc::Body body(model, nullptr);
    const uint32_t V = model.vertex_count();
    std::vector<float> xyz(3ull * V);
    ssc::kernels::planar_to_xyz(body.posed(), V, xyz.data(), 12);
    const auto& tris = model.data().mesh.triangles;
    ssc::exporters::MeshView mesh;
    mesh.vertex_count = V;
    mesh.positions = xyz.data();
    mesh.triangle_count = uint32_t(tris.size() / 3);
    mesh.triangles = tris.data();
    ssc::exporters::write_ply((out / "ply" / "mesh_binary.ply").string(), mesh);
    ssc::exporters::write_obj((out / "obj" / "mesh.obj").string(), mesh);
    mesh.normals = body.normals();
    mesh.triangle_count = 0;
    ssc::exporters::write_ply((out / "ply" / "points_normals_binary.ply").string(), mesh);
    ssc::exporters::write_obj((out / "obj" / "points_normals.obj").string(), mesh);
    put(out / "ply" / "ascii.ply",
        "ply\nformat ascii 1.0\ncomment a triangle with normals\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
    std::string big = "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
                      "end_header\n";
    for (double v : {0.0, 1.0, 2.0, -1.0, 0.5, 3.0}) {
        unsigned char b[8];
        std::memcpy(b, &v, 8);
        for (int i = 7; i >= 0; --i) big.push_back(char(b[i]));
    }
    put(out / "ply" / "big_endian.ply", big);

    // Landmarks and a depth image.
    std::vector<ssc::io::LandmarkRecord> landmarks;
    for (uint32_t l = 0; l < 5; ++l)
        landmarks.push_back({l + 1, l == 0 ? "Sellion" : l == 1 ? "Rt. Acromion" : "Lt. Dactylion", Eigen::Vector3d(0.1 * l, 1.0 + l, -0.2)});
    ssc::io::write_lnd((out / "lnd" / "subject.lnd").string(), "fuzz seed", landmarks);
    ssc::io::DepthImage depth;
    depth.width = 8, depth.height = 6;
    depth.depth.assign(48, 0.f);
    for (std::size_t i = 0; i < depth.depth.size(); ++i) depth.depth[i] = i % 5 ? 1.5f + 0.01f * float(i) : 0.f;
    depth.has_intrinsics = true, depth.fx = depth.fy = 6, depth.cx = 4, depth.cy = 3;
    depth.has_pose = true;
    ssc::io::write_pgm_depth((out / "pgm" / "camera.pgm").string(), depth);
    depth.has_intrinsics = depth.has_pose = false;
    ssc::io::write_pgm_depth((out / "pgm" / "plain.pgm").string(), depth);
    // A registration report as sscape register writes it for the built-in model (its joints), with
    // and without the model fit; the scan tables, their first byte choosing the kind.
    ssc_model* builtin = nullptr;
    if (ssc_model_load_default(nullptr, &builtin) != SSC_OK) return 1;
    const uint32_t joints = ssc_model_joint_count(builtin);
    const char* model_name = "";
    if (ssc_model_get_metadata(builtin, SSC_METADATA_NAME, &model_name) != SSC_OK) return 1;
    // Fit parameters as `sscape fit --params` writes them (checked by the model's name here: the
    // digest lives in the offline API), rotations keyed by joint name.
    std::string by_joint;
    for (uint32_t j = 0; j < joints; ++j) {
        const char* joint = "";
        if (ssc_model_get_joint_name(builtin, j, &joint) != SSC_OK) return 1;
        by_joint += std::string(j ? ", " : "") + "\"" + joint + "\": [0, 0, " + (j == 1 ? "0.6, 0.8" : "0, 1") + "]";
    }
    put(out / "params" / "fit.json", std::string(R"({"model": ")") + model_name + R"(", "shape": [0.5, -1.25, 2.0], "frames": [{"rotations_xyzw": {)" +
                                         by_joint + R"(}, "translation_m": [0.01, 0.92, -0.3], "scale": 1}]})" + "\n");
    ssc_model_release(builtin);
    const std::string quality = R"({"scan_to_registration_mean_m": 0.001, "scan_to_registration_median_m": 0.0008, )"
                                R"("scan_to_registration_p95_m": 0.003, "scan_points": 6000, "scan_points_beyond_20_mm": 3, )"
                                R"("vertices_within_2_5_10_20_mm": [0.5, 0.7, 0.8, 0.9]})";
    const std::string report = R"({"scan": "scans/s1.ply", "scan_up": "z", "scan_units_to_metres": 0.001, "fit_segments": false, )"
                               R"("seconds": 1.5, "fit_seconds": 0.5, "rounds": 6, "solves": 18, "model_digest": "0123456789abcdef", )"
                               R"("scan_digest": "fedcba9876543210", "quality": )" + quality + R"(, "regions": {"head": )" + quality +
                               R"(, "trunk": )" + quality + "}";
    std::string rotations;
    for (uint32_t j = 0; j < joints; ++j) rotations += std::string(j ? ", " : "") + "0, 0, 0, 1";
    put(out / "report" / "without_fit.json", report + "}\n");
    put(out / "report" / "with_fit.json", report + R"(, "fit": {"shape": [0.5, -0.25, 1.0], "rotations_xyzw": [)" + rotations +
                                               R"(], "translation_m": [0, 0.9, 0.1], "scale": 1}})" + "\n");
    put(out / "tables" / "decisions.csv", "dscan,decision,reason,by\ns1,accept,,person\ns2,reject,\"arm, left\",person\ns3,accept,,auto\n");
    put(out / "tables" / "attributes.csv", "ascan,age,stature_m\ns1,31,1.72\ns2,45,1.65\n\"s3\",28,1.80\n");
    std::printf("seed corpora written to %s\n", out.c_str());
    return 0;
}
