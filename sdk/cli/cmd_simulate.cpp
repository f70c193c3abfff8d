// `sscape simulate`: a random body of the model measured as a scanner would: a point cloud with
// noise, holes and outliers (PLY with normals), landmarks with placement noise (CAESAR .lnd, mm),
// and the true mesh (OBJ) to compare fits with.
#include "cli.hpp"

#include "capi/handles.hpp"
#include "export/mesh_writers.hpp"
#include "io/writers.hpp"
#include "simulation/simulate.hpp"

#include <cstdio>

namespace ssc::cli {

int cmd_simulate(const std::vector<std::string>& args) {
    std::string model_path, prefix;
    uint32_t seed = 1;
    double pose_amount = 1, landmark_noise = 0.01, heading = 0;
    simulation::CloudSpec spec;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto number = [&]() {
            const auto v = parse_floats(option_value(args, i), a);
            if (v.size() != 1 || v[0] < 0) throw UsageError(a + " needs one non-negative number");
            return double(v[0]);
        };
        if (a == "-o" || a == "--output") prefix = option_value(args, i);
        else if (a == "--seed") seed = parse_count(option_value(args, i), a);
        else if (a == "--points") spec.points = parse_count(option_value(args, i), a);
        else if (a == "--noise") spec.noise = number();
        else if (a == "--missing") spec.missing = number();
        else if (a == "--outliers") spec.outliers = number();
        else if (a == "--landmark-noise") landmark_noise = number();
        else if (a == "--pose-amount") pose_amount = number();
        else if (a == "--heading") heading = number();
        else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "'");
        else if (model_path.empty()) model_path = a;
        else throw UsageError("unexpected argument '" + a + "'");
    }
    if (prefix.empty()) throw UsageError("simulate needs -o PREFIX");
    if (spec.missing >= 1 || spec.outliers >= 1) throw UsageError("--missing and --outliers are fractions below 1");
    if (spec.points < 16 || spec.points > 10000000) throw UsageError("--points must be 16..10000000");
    ssc_model* model = load_model(model_path);
    struct Guard {
        ssc_model* m;
        ~Guard() { ssc_model_release(m); }
    } guard{model};
    const Model& m = model->model;
    std::mt19937 rng(seed);
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, pose_amount), Eigen::Vector3d::Zero());
    simulation::transform_body(truth, Eigen::AngleAxisd(heading * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d::Zero());
    const auto cloud = simulation::simulate_cloud(m, truth, spec, rng);
    std::vector<float> pts, nrm;
    for (std::size_t i = 0; i < cloud.points.size(); ++i)
        for (int a = 0; a < 3; ++a) pts.push_back(float(cloud.points[i][a])), nrm.push_back(float(cloud.normals[i][a]));
    exporters::MeshView pv;
    pv.vertex_count = uint32_t(cloud.points.size());
    pv.positions = pts.data();
    pv.normals = nrm.data();
    exporters::write_ply(prefix + "_scan.ply", pv);
    std::vector<io::LandmarkRecord> lnd;
    for (const auto& t : simulation::simulate_landmarks(m, truth, landmark_noise, false, rng))
        lnd.push_back({t.landmark + 1, m.data().landmarks[t.landmark].name, t.position});
    io::write_lnd(prefix + ".lnd", "simulated seed " + std::to_string(seed), lnd);
    std::vector<float> tv;
    for (const auto& v : truth.vertices)
        for (int a = 0; a < 3; ++a) tv.push_back(float(v[a]));
    exporters::MeshView mv;
    mv.vertex_count = m.vertex_count();
    mv.positions = tv.data();
    mv.triangle_count = m.triangle_count();
    mv.triangles = m.data().mesh.triangles.data();
    exporters::write_obj(prefix + "_truth.obj", mv);
    std::printf("wrote %s_scan.ply (%zu points: %.1f mm noise, %.0f %% missing, %.1f %% outliers), %s.lnd (%zu landmarks, %.1f mm noise), "
                "%s_truth.obj\n",
                prefix.c_str(), cloud.points.size(), spec.noise * 1e3, spec.missing * 100, spec.outliers * 100, prefix.c_str(), lnd.size(),
                landmark_noise * 1e3, prefix.c_str());
    return 0;
}

}  // namespace ssc::cli
