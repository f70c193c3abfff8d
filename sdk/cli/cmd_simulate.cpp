// `sscape simulate`: a random body of the model measured as a scanner would: a point cloud with
// noise, holes and outliers (PLY with normals), landmarks with placement noise (CAESAR .lnd, mm),
// optionally depth images from cameras in front of and behind the body (16-bit PGM in mm with the
// camera in its header), and the true mesh (OBJ) to compare fits with; or a collection of them
// (--count), scans and truths in separate folders.
#include "cli.hpp"

#include "capi/cpp_access.hpp"
#include "export/mesh_writers.hpp"
#include "io/writers.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/simulate.hpp"

#include "common/text.hpp"
#include "progress.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace ssc::cli {

namespace {

struct Options {
    std::string model_path, prefix, depth;
    uint32_t seed = 1, count = 0;
    double pose_amount = 1, landmark_noise = 0.003, heading = 0;
    simulation::CloudSpec spec;
    simulation::DepthCameraSpec camera_spec;
};

// Where one simulated body's files go: the scan, its landmarks and depth images side by side (what
// a scanner gives), the truth apart where asked (so a folder of scans holds only scans).
struct Paths {
    std::string scan, landmarks, depth_prefix, truth;
};

// One random body measured; returns what was written, for the command's line.
std::string simulate_one(const Model& m, const Options& o, uint32_t seed, const Paths& to) {
    const simulation::CloudSpec& spec = o.spec;
    const simulation::DepthCameraSpec& camera_spec = o.camera_spec;
    std::vector<std::string> views;  // "front", "back"
    if (o.depth == "front" || o.depth == "back") views = {o.depth};
    else if (!o.depth.empty()) views = {"front", "back"};
    std::mt19937 rng(seed);
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, o.pose_amount), Eigen::Vector3d::Zero());
    simulation::transform_body(truth, Eigen::AngleAxisd(o.heading * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d::Zero());
    const auto cloud = simulation::simulate_cloud(m, truth, spec, rng);
    std::vector<float> pts, nrm;
    for (std::size_t i = 0; i < cloud.points.size(); ++i)
        for (int a = 0; a < 3; ++a) pts.push_back(float(cloud.points[i][a])), nrm.push_back(float(cloud.normals[i][a]));
    exporters::MeshView pv;
    pv.vertex_count = uint32_t(cloud.points.size());
    pv.positions = pts.data();
    pv.normals = nrm.data();
    exporters::write_ply(to.scan, pv);
    std::vector<io::LandmarkRecord> lnd;
    for (const auto& t : simulation::simulate_landmarks(m, truth, o.landmark_noise, false, rng))
        lnd.push_back({t.landmark + 1, m.data().landmarks[t.landmark].name, t.position});
    io::write_lnd(to.landmarks, "simulated seed " + std::to_string(seed), lnd);
    std::string depth_note;
    if (!views.empty()) {
        // Cameras 2.8 m from the body's centre at its height, in front (+z) and behind (-z): a
        // 640 x 480 Kinect-class sensor then sees the whole body with raised arms.
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (const auto& v : truth.vertices) centre += v;
        centre /= double(truth.vertices.size());
        for (const auto& view : views) {
            const Eigen::Vector3d eye = centre + Eigen::Vector3d(0, 0, view == "front" ? 2.8 : -2.8);
            const fitting::PinholeCamera cam = simulation::look_at(eye, centre, camera_spec);
            io::DepthImage img;
            img.width = camera_spec.width, img.height = camera_spec.height;
            img.depth = simulation::render_depth(m, truth, cam, camera_spec, rng);
            img.has_intrinsics = img.has_pose = true;
            img.fx = cam.fx, img.fy = cam.fy, img.cx = cam.cx, img.cy = cam.cy;
            img.camera_to_world.topLeftCorner<3, 3>() = cam.rotation;
            img.camera_to_world.topRightCorner<3, 1>() = cam.position;
            const std::string path = to.depth_prefix + "_" + view + ".pgm";
            io::write_pgm_depth(path, img);
            depth_note += ", " + path;
        }
        depth_note += format_text(" (%u x %u depth in mm, %.1f mm noise)", camera_spec.width, camera_spec.height, camera_spec.noise * 1e3);
    }
    std::vector<float> tv;
    for (const auto& v : truth.vertices)
        for (int a = 0; a < 3; ++a) tv.push_back(float(v[a]));
    exporters::MeshView mv;
    mv.vertex_count = m.vertex_count();
    mv.positions = tv.data();
    mv.triangle_count = m.triangle_count();
    mv.triangles = m.data().mesh.triangles.data();
    exporters::write_obj(to.truth, mv);
    return format_text("%s (%zu points: %.1f mm noise, %.0f %% missing, %.1f %% outliers), %s (%zu landmarks, %.1f mm noise), %s%s",
                       to.scan.c_str(), cloud.points.size(), spec.noise * 1e3, spec.missing * 100, spec.outliers * 100,
                       to.landmarks.c_str(), lnd.size(), o.landmark_noise * 1e3, to.truth.c_str(), depth_note.c_str());
}

int run_simulate(const Options& o) {
    ssc_model* model = load_model(o.model_path);
    const Handles guard(model);
    const Model& m = model_of(model);
    if (o.count == 0) {
        create_parent_folder(o.prefix);
        const std::string& p = o.prefix;
        std::printf("wrote %s\n", simulate_one(m, o, o.seed, {p + "_scan.ply", p + ".lnd", p, p + "_truth.obj"}).c_str());
        return 0;
    }
    // A collection: OUT/scans holds what a scanner gives (NAME.ply with NAME.lnd beside it, as a scan
    // folder is read), OUT/truth the true meshes (NAME.obj), which no scan folder should hold.
    const std::filesystem::path out(o.prefix), scans = out / "scans", truths = out / "truth";
    std::filesystem::create_directories(scans);
    std::filesystem::create_directories(truths);
    const int digits = std::max(3, int(std::to_string(o.count).size()));
    Progress progress("simulate");
    for (uint32_t i = 0; i < o.count; ++i) {
        if (!progress.update("scan " + std::to_string(i + 1) + " of " + std::to_string(o.count))) {
            std::fprintf(stderr, "sscape simulate: cancelled (Ctrl-C) after %u of %u scans; those %u are complete, in %s\n", i, o.count, i,
                         scans.string().c_str());
            return 130;
        }
        const std::string name = format_text("sim_%0*u", digits, i + 1);
        const std::string stem = (scans / name).string();
        const std::string line = simulate_one(m, o, o.seed + i, {stem + ".ply", stem + ".lnd", stem, (truths / (name + ".obj")).string()});
        progress.clear();
        std::printf("wrote %s\n", line.c_str());
    }
    std::printf("wrote %u scans with their landmarks to %s and their true meshes to %s\n", o.count, scans.string().c_str(),
                truths.string().c_str());
    return 0;
}

}  // namespace

Run add_simulate(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("simulate", "a random posed body of the model measured as a scanner would: PREFIX_scan.ply (noise, "
                                                 "holes, outliers), PREFIX.lnd (CAESAR landmarks in mm), optional depth images "
                                                 "PREFIX_front.pgm / PREFIX_back.pgm, and the truth PREFIX_truth.obj");
    add_model_argument(*c, o->model_path);
    c->add_option("-o,--output", o->prefix, "where the files go: PREFIX_scan.ply, PREFIX.lnd, ... (with --count: a folder)")
        ->required()->type_name("PREFIX|DIR");
    c->add_option("--seed", o->seed, "random seed (shape, pose, noise); with --count, the first scan's (then SEED+1, ...)")->capture_default_str();
    c->add_option("--count", o->count, "a collection of N scans: DIR/scans/sim_001.ply with sim_001.lnd (and depth images) beside it, "
                                       "the true meshes in DIR/truth/sim_001.obj; Ctrl-C stops it, keeping the scans already written")
        ->check(CLI::Range(1u, 100000u))->type_name("N");
    c->add_option("--points", o->spec.points, "points in the scan")->check(CLI::Range(16u, 10000000u))->capture_default_str();
    c->add_option("--noise", o->spec.noise, "scan noise, metres (standard deviation)")->check(finite_in(0, 0.1))->capture_default_str();
    c->add_option("--missing", o->spec.missing, "fraction of the surface left out, as 20 round holes")
        ->check(finite_in(0, 0.95))->capture_default_str();
    c->add_option("--outliers", o->spec.outliers, "fraction of points replaced by clutter around the body")
        ->check(finite_in(0, 0.95))->capture_default_str();
    c->add_option("--landmark-noise", o->landmark_noise, "landmark placement noise, metres per axis (3 mm: about 5 mm in space, as a person places them)")->check(finite_in(0, 0.1))->capture_default_str();
    c->add_option("--pose-amount", o->pose_amount, "how far the random pose goes: 0 rest, 1 the usual range, up to 3")
        ->check(finite_in(0, 3))->capture_default_str();
    c->add_option("--heading", o->heading, "turn the body about the vertical, degrees")->check(finite_in(-360, 360))->capture_default_str();
    c->add_option("--depth", o->depth, "also render depth images from a camera in front, behind, or both")
        ->check(CLI::IsMember({"front", "back", "front,back", "both"}).description(""))->type_name("front|back|front,back");
    c->add_option("--depth-noise", o->camera_spec.noise, "depth noise, metres (standard deviation)")
        ->check(finite_in(0, 0.1))->capture_default_str();
    return [o] { return run_simulate(*o); };
}

}  // namespace ssc::cli
