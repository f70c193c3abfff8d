#include "testing/simulated_collection.hpp"

#include "export/mesh_writers.hpp"
#include "io/writers.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/simulate.hpp"
#include "training/makehuman/assets.hpp"
#include "training/population.hpp"

#include <cstdio>
#include <filesystem>
#include <random>

namespace ssc::testing {

SimulatedCollection simulate_collection(const std::string& makehuman, const Model& model, const CollectionSpec& spec, const std::string& folder) {
    const uint32_t V = model.vertex_count();
    training::mh::Assets assets = training::mh::load_assets(makehuman);
    training::PopulationSpec ps;
    ps.count = spec.scans + spec.extra;
    ps.seed = spec.seed;
    const std::vector<training::BodyParams> people = training::sample_population(assets, ps);
    const std::size_t trained = assets.modifiers.size();
    training::mh::add_modifier_groups(assets, "modeling_modifiers.json", {"neck", "head", "armslegs"});
    std::mt19937 rng(spec.variation_seed);
    SimulatedCollection out;
    for (const training::BodyParams& person : people) {
        const std::vector<float> xyz = training::beyond_model_body(assets, person, trained, rng);
        std::vector<Eigen::Vector3d> rest(V);
        for (uint32_t v = 0; v < V; ++v) rest[v] = Eigen::Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
        out.rest.push_back(std::move(rest));
    }
    std::filesystem::create_directories(folder);
    std::mt19937 placement(spec.variation_seed + 1);  // the landmarks' own draws: the scans stay the same
    for (uint32_t s = 0; s < spec.scans; ++s) {
        out.poses.push_back(simulation::scanning_pose(model, rng, spec.pose_spread));
        const simulation::TrueBody body = simulation::pose_rest_vertices(model, out.rest[s], out.poses.back(), Eigen::Vector3d::Zero());
        out.truth.push_back(body.vertices);
        simulation::BoothSpec booth;
        booth.points = spec.points;
        const fitting::PointCloud cloud = simulation::booth_scan(model, body, booth, rng);
        std::vector<float> xyz, normals;
        for (std::size_t i = 0; i < cloud.points.size(); ++i)
            for (int a = 0; a < 3; ++a) xyz.push_back(float(cloud.points[i][a])), normals.push_back(float(cloud.normals[i][a]));
        char name[16];
        std::snprintf(name, sizeof name, "b%03u", s);
        const std::string path = (std::filesystem::path(folder) / (std::string(name) + ".ply")).string();
        exporters::MeshView mesh;
        mesh.vertex_count = uint32_t(cloud.points.size());
        mesh.positions = xyz.data();
        mesh.normals = normals.data();
        exporters::write_ply(path, mesh);
        std::string landmarks;
        if (spec.landmark_noise >= 0) {
            landmarks = (std::filesystem::path(folder) / (std::string(name) + ".lnd")).string();
            std::vector<io::LandmarkRecord> records;
            for (const auto& t : simulation::simulate_landmarks(model, body, spec.landmark_noise, true, placement))
                records.push_back({t.landmark + 1, model.data().landmarks[t.landmark].name, t.position});
            io::write_lnd(landmarks, std::string("simulated ") + name, records);
        }
        out.scans.push_back({name, path, landmarks});
    }
    return out;
}

}  // namespace ssc::testing
