#include "body_inputs.hpp"
#include "cli.hpp"
#include "progress.hpp"

#include "common/files.hpp"
#include "export/body_export.hpp"
#include "render/body_sheet.hpp"
#include "render/landmark_picture.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

namespace ssc::cli {
namespace {

struct Options {
    std::string model, out;
    std::string shape_text, translation_text, sliders_text, measure_text, sex_text;  // as given; parsed by finish()
    std::vector<float> shape, translation;
    std::string pose, png, landmarks_png, limits, params;
    std::vector<std::pair<std::string, float>> sliders, measurements;  // NAME=VALUE lists
    float sex = std::nanf(""), age = std::nanf("");
    uint32_t random = 0, seed = 1;
    bool normals = false;
    std::vector<float> hands;  // --hands: left and right closure, or one for both
    std::vector<std::string> segment_texts;  // --segment NAME=C1,C2,...
    std::string lod = "0";                   // --lod: a level of detail, by number or name
    std::string morphs;                      // --morphs: K components, or "sliders"
};

// --morphs: "sliders" or a component count, as the export options take them.
ssc_export_def export_def(ssc_model* model, const std::string& morphs, uint32_t level) {
    ssc_export_def def;
    ssc_export_def_init(&def, sizeof def);
    def.level = level;
    if (morphs.empty()) return def;
    if (morphs == "sliders") {
        if (ssc_model_slider_count(model) == 0) throw UsageError("--morphs sliders: the model has no semantic sliders");
        def.morphs = SSC_MORPHS_SLIDERS;
        return def;
    }
    const uint32_t K = ssc_model_shape_count(model);
    char* end = nullptr;
    const unsigned long k = std::strtoul(morphs.c_str(), &end, 10);
    if (!std::isdigit(static_cast<unsigned char>(morphs[0])) || *end || k < 1 || k > K)
        throw UsageError("--morphs: '" + morphs + "' is neither sliders nor a component count from 1 to " + std::to_string(K));
    def.morphs = SSC_MORPHS_COMPONENTS;
    def.morph_count = uint32_t(k);
    return def;
}

// --lod: the level's number (0 the full mesh) or name, checked against the model's.
uint32_t find_level(ssc_model* model, const std::string& text) {
    if (text == "all") return SSC_LEVEL_ALL;
    const uint32_t count = ssc_model_level_count(model);
    std::string names;
    for (uint32_t l = 0; l < count; ++l) {
        ssc_level_info info{};
        info.struct_size = sizeof info;
        check(ssc_model_get_level_info(model, l, &info), "level");
        if (text == info.name || text == std::to_string(l)) return l;
        names += std::string(names.empty() ? "" : ", ") + std::to_string(l) + " " + info.name + " (" + std::to_string(info.vertex_count) + " vertices)";
    }
    throw UsageError("--lod: the model has no level '" + text + "' (its levels: " + names + ")");
}

// --segment: each segment's coefficients, set on the body on top of its whole-body shape.
void set_segments(ssc_model* model, ssc_body* body, const std::vector<std::string>& texts) {
    std::vector<std::string> seen;
    for (const std::string& text : texts) {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError("--segment: '" + text + "' is not NAME=C1,C2,...");
        const std::string name = text.substr(0, eq);
        if (std::find(seen.begin(), seen.end(), name) != seen.end()) throw UsageError("--segment: " + name + " is given twice");
        seen.push_back(name);
        uint32_t index = 0;
        if (ssc_model_find_segment(model, name.c_str(), &index) != SSC_OK) {
            std::string names;
            for (uint32_t s = 0; s < ssc_model_segment_count(model); ++s) {
                ssc_segment_info info{};
                info.struct_size = sizeof info;
                check(ssc_model_get_segment_info(model, s, &info), "segment");
                names += std::string(names.empty() ? "" : ", ") + info.name;
            }
            throw UsageError("--segment: the model has no segment '" + name + "' (" +
                             (names.empty() ? std::string("it has no segment shape spaces: sscape learn --segment-components makes them")
                                            : "its segments: " + names) + ")");
        }
        const std::vector<float> c = parse_floats(text.substr(eq + 1), "--segment " + name);
        check(ssc_body_set_segment_shape(body, index, c.data(), uint32_t(c.size())), "--segment " + name);
    }
}

// What CLI11 cannot check: the number lists and the combinations.
void finish(Options& o) {
    if (!o.shape_text.empty()) o.shape = parse_floats(o.shape_text, "--shape");
    if (!o.translation_text.empty()) o.translation = parse_floats(o.translation_text, "--translation");
    if (!o.sliders_text.empty()) o.sliders = parse_named(o.sliders_text, "--sliders");
    if (!o.measure_text.empty()) o.measurements = parse_named(o.measure_text, "--measure");
    if (!o.sex_text.empty()) o.sex = o.sex_text == "male" ? 1.f : 0.f;
    if (!o.translation.empty() && o.translation.size() != 3) throw UsageError("--translation needs 3 numbers");
    if ((!std::isnan(o.sex) || !std::isnan(o.age)) && o.measurements.empty()) throw UsageError("--sex and --age go with --measure");
    exporters::format_of(o.out);  // refuses other extensions, naming the formats
}

// "--pose sitting", "--pose upperarm_l=0,0,-0.5;lowerarm_l=0.3,0,0" or both ("t_pose;head=0.3,0,0"):
// a named pose, then axis-angle radians per named joint. Returns quaternions (x y z w per joint).
std::vector<float> parse_pose(ssc_model* model, const std::string& text) {
    const uint32_t J = ssc_model_joint_count(model);
    std::vector<float> q(4ull * J, 0.f);
    for (uint32_t j = 0; j < J; ++j) q[4 * j + 3] = 1.f;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ';')) {
        if (item.empty()) continue;
        const auto eq = item.find('=');
        if (eq == std::string::npos) {
            if (ssc_model_get_named_pose(model, item.c_str(), q.data(), J) != SSC_OK)
            {
                std::string names;
                for (uint32_t i = 0; i < ssc_named_pose_count(); ++i) {
                    const char* n = "";
                    ssc_named_pose_get_info(i, &n, nullptr);
                    names += std::string(i ? ", " : "") + n;
                }
                throw UsageError("--pose: '" + item + "' is neither a named pose (" + names + ") nor JOINT=AX,AY,AZ");
            }
            continue;
        }
        const std::string name = item.substr(0, eq);
        uint32_t j = 0;
        if (ssc_model_find_joint(model, name.c_str(), &j) != SSC_OK) {
            std::string names;
            for (uint32_t k = 0; k < ssc_model_joint_count(model); ++k) {
                const char* n = "";
                ssc_model_get_joint_name(model, k, &n);
                names += std::string(k ? " " : "") + n;
            }
            throw UsageError("--pose: the model has no joint '" + name + "'; its joints: " + names);
        }
        const std::vector<float> v = parse_floats(item.substr(eq + 1), "--pose " + name);
        if (v.size() != 3) throw UsageError("--pose " + name + " needs 3 numbers (axis * angle in radians)");
        const double angle = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
        // A rotation vector longer than a full turn is no joint rotation: most likely degrees.
        if (angle > 2 * M_PI)
            throw UsageError("--pose " + name + ": a rotation of " + std::to_string(angle) +
                             " radians is more than a full turn; angles are in radians (degrees x pi / 180)");
        check(ssc_rotation_from_axis_angle(v.data(), &q[4 * j]), "--pose " + name);
    }
    return q;
}

// Many bodies are written into a hidden folder beside their destination and moved into place once
// all are written: a run stopped by Ctrl-C or an error leaves nothing behind (one body is written
// atomically by the library itself).
class Staging {
public:
    Staging(const std::string& out, uint32_t n) {
        if (n <= 1) return;
        const std::filesystem::path parent = std::filesystem::path(out).parent_path();
        std::string pattern = ((parent.empty() ? std::filesystem::path(".") : parent) / ".sscape-synth-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a folder beside " + out + ": " + std::strerror(errno));
        folder_ = pattern;
    }
    ~Staging() {
        std::error_code ignored;
        if (!folder_.empty()) std::filesystem::remove_all(folder_, ignored);
    }
    Staging(const Staging&) = delete;
    Staging& operator=(const Staging&) = delete;
    // Where the body meant for path is written now.
    std::string path(const std::string& final_path) {
        if (folder_.empty()) return final_path;
        finals_.push_back(final_path);
        return (std::filesystem::path(folder_) / std::filesystem::path(final_path).filename()).string();
    }
    // Moves every written body into place (renames within one file system).
    void commit() {
        for (const auto& final_path : finals_)
            std::filesystem::rename(std::filesystem::path(folder_) / std::filesystem::path(final_path).filename(), final_path);
    }

private:
    std::string folder_;
    std::vector<std::string> finals_;
};

std::string numbered(const std::string& out, uint32_t i, uint32_t n) {
    if (n <= 1) return out;
    char buf[16];
    std::snprintf(buf, sizeof buf, "_%03u", i);
    return with_suffix(out, buf);
}

// --sliders moves the named sliders from the given shape; --measure then makes the body to measure
// and prints what it reached.
void shape_by_meaning(ssc_model* model, ssc_body* body, const Options& o) {
    set_sliders(model, body, o.sliders);
    if (o.measurements.empty()) return;
    std::vector<uint32_t> which;
    std::vector<float> values;
    for (const auto& [name, value] : o.measurements) {
        uint32_t m = 0;
        if (ssc_measurement_find(name.c_str(), &m) != SSC_OK)
            throw UsageError("--measure: no measurement '" + name + "' (sscape measure --definitions lists them)");
        which.push_back(m);
        values.push_back(value);
    }
    ssc_made_to_measure_def def;
    ssc_made_to_measure_def_init(&def, sizeof def);
    def.sex = o.sex;
    def.age = o.age;
    std::vector<float> achieved(ssc_measurement_count());
    uint32_t converged = 0;
    check(ssc_body_make_to_measure(body, which.data(), values.data(), uint32_t(which.size()), &def, achieved.data(),
                                   uint32_t(achieved.size()), &converged),
          "made to measure");
    std::printf("%-18s %10s %10s\n", "made to measure", "requested", "achieved");
    for (std::size_t i = 0; i < which.size(); ++i)
        std::printf("%-18s %10.4f %10.4f\n", o.measurements[i].first.c_str(), values[i], achieved[which[i]]);
    if (!converged) std::printf("note: not every request was reached within 0.5 mm (the combination may be unusual)\n");
}

int run_synth(Options o) {
    finish(o);
    ssc_model* model = load_model(o.model);
    Handles guard(model);

    const uint32_t written = find_level(model, o.lod);
    if (written != 0 && !o.landmarks_png.empty()) throw UsageError("--landmarks-png draws the full mesh: leave --lod out");
    if (written == SSC_LEVEL_ALL && exporters::format_of(o.out) != exporters::BodyFormat::Glb)
        throw UsageError("--lod all writes every level into one glTF file: the output must be .glb");
    if (!o.morphs.empty() && exporters::format_of(o.out) != exporters::BodyFormat::Glb)
        throw UsageError("--morphs: morph targets are written into glTF files: the output must be .glb");
    const ssc_export_def def = export_def(model, o.morphs, written);
    const uint32_t level = written == SSC_LEVEL_ALL ? 0 : written;  // what the table and --png show
    ssc_level_info info{};
    info.struct_size = sizeof info;
    check(ssc_model_get_level_info(model, level, &info), "level");
    const uint32_t V = info.vertex_count, T = info.triangle_count;
    const uint32_t K = ssc_model_shape_count(model), J = ssc_model_joint_count(model);
    if (o.shape.size() > K) throw UsageError("--shape has " + std::to_string(o.shape.size()) + " values; the model has " + std::to_string(K) + " components");
    std::vector<uint32_t> tris(3ull * T);
    check(ssc_model_get_level_triangles(model, level, tris.data(), T), "triangles");
    check(ssc_body_create(model, nullptr, &guard.body), "body");
    const FitParams fitted = o.params.empty() ? FitParams{} : read_params(model, o.params);
    set_fit_segments(model, guard.body, fitted);  // --segment below sets those it names on top
    set_segments(model, guard.body, o.segment_texts);
    std::vector<float> pose = o.params.empty() ? parse_pose(model, o.pose) : fitted.pose;
    if (!o.hands.empty())
        check(ssc_model_close_hands(model, o.hands.front(), o.hands.back(), pose.data(), J), "--hands");
    const float* translation = !o.params.empty() ? fitted.translation.data() : o.translation.empty() ? nullptr : o.translation.data();
    if (o.limits.empty()) {
        check(ssc_body_set_pose(guard.body, pose.data(), J, translation), "pose");
    } else {
        uint32_t outside = 0;
        check(ssc_body_set_pose_limited(guard.body, pose.data(), J, translation, o.limits == "clamp" ? SSC_LIMITS_CLAMP : SSC_LIMITS_REJECT,
                                        &outside),
              "pose");
        if (outside) std::printf("pose: %u joint(s) clamped to their anatomical limits\n", outside);
    }

    // Random shapes: standard normal coefficients, truncated at 2.5 SD so no body is implausibly extreme.
    std::vector<float> random(std::size_t(o.random) * K);
    if (o.random) check(ssc_model_sample_shapes(model, o.seed, o.random, 2.5f, random.data(), uint32_t(random.size())), "random shapes");
    const uint32_t n = o.random ? o.random : 1;
    std::vector<float> verts(3ull * V);
    std::vector<std::vector<float>> rendered;
    create_parent_folder(o.out);
    Staging staging(o.out, n);
    std::vector<float> first_vertices, first_landmarks;
    std::string first_path;
    Progress progress("synth");
    for (uint32_t i = 0; i < n; ++i) {
        if (!progress.update("body " + std::to_string(i + 1) + " of " + std::to_string(n))) {
            std::fprintf(stderr, "sscape synth: cancelled (Ctrl-C) after %u of %u bodies; nothing written\n", i, n);
            return 130;
        }
        std::vector<float> shape = o.params.empty() ? o.shape : fitted.shape;
        if (o.random) shape.assign(random.begin() + std::ptrdiff_t(i) * K, random.begin() + std::ptrdiff_t(i + 1) * K);
        check(ssc_body_set_shape(guard.body, shape.data(), uint32_t(shape.size())), "shape");
        if (!o.sliders.empty() || !o.measurements.empty()) {
            shape_by_meaning(model, guard.body, o);
            shape.resize(K);
            check(ssc_body_get_shape(guard.body, shape.data(), K), "shape");
        }
        check(ssc_body_get_level_vertices(guard.body, level, verts.data(), V, 0), "vertices");
        // The library writes the file: OBJ with normals and UVs, binary PLY, or rigged glTF.
        const std::string path = numbered(o.out, i, n);
        check(ssc_body_export(guard.body, staging.path(path).c_str(), &def), path);
        if (!o.png.empty() && rendered.size() < 20) rendered.push_back(verts);
        if (!o.landmarks_png.empty() && i == 0) {  // drawn once every body is written
            const uint32_t L = ssc_model_landmark_count(model);
            if (L == 0) throw std::runtime_error("--landmarks-png: the model has no landmarks");
            first_landmarks.resize(3ull * L);
            check(ssc_body_get_landmarks(guard.body, first_landmarks.data(), L, 0), "landmarks");
            first_vertices = verts, first_path = path;
        }
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
        for (uint32_t v = 0; v < V; ++v)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], verts[3 * v + a]);
                hi[a] = std::max(hi[a], verts[3 * v + a]);
            }
        progress.clear();  // the row goes where the progress line was
        if (i == 0) std::printf("%-28s %9s %9s %9s   first shape coefficients\n", "file", "height_m", "width_m", "depth_m");
        std::printf("%-28s %9.3f %9.3f %9.3f  ", path.c_str(), hi[1] - lo[1], hi[0] - lo[0], hi[2] - lo[2]);
        for (std::size_t k = 0; k < std::min<std::size_t>(3, shape.size()); ++k) std::printf(" %+.2f", shape[k]);
        std::printf("\n");
    }
    staging.commit();
    if (!first_landmarks.empty()) {
        render::write_landmark_picture(o.landmarks_png, first_vertices, tris, first_landmarks);
        std::printf("drew the %zu landmarks of %s (front, back, side; head and trunk close up) to %s\n", first_landmarks.size() / 3,
                    first_path.c_str(), o.landmarks_png.c_str());
    }
    if (written == SSC_LEVEL_ALL)
        std::printf("wrote %u bod%s, each with its %u levels of detail (nodes _LOD0 to _LOD%u)\n", n, n == 1 ? "y" : "ies",
                    ssc_model_level_count(model), ssc_model_level_count(model) - 1);
    else
        std::printf("wrote %u bod%s of %u vertices, %u triangles%s\n", n, n == 1 ? "y" : "ies", V, T,
                    level ? (std::string(" (level of detail ") + std::to_string(level) + ", " + info.name + ")").c_str() : "");
    if (!o.png.empty()) {
        render::write_body_sheet(o.png, rendered, tris);
        std::printf("rendered %zu bod%s (front and side views) to %s\n", rendered.size(), rendered.size() == 1 ? "y" : "ies",
                    o.png.c_str());
    }
    return 0;
}

}  // namespace

Run add_synth(CLI::App& app) {
    auto o = std::make_shared<Options>();
    CLI::App* c = app.add_subcommand("synth", "write bodies of the model: a given shape and pose, random shapes, bodies by semantic "
                                              "sliders or made to measure, or a fit read back from its parameters");
    add_model_argument(*c, o->model);
    c->add_option("-o,--output", o->out, "the body to write: OBJ (normals, UVs), binary PLY or rigged glTF; with --random N, "
                                         "OUT_000.obj, OUT_001.obj, ...")
        ->required()->type_name("OUT.obj|.ply|.glb");
    CLI::Option* shape = c->add_option("--shape", o->shape_text, "shape coefficients in standard deviations; those left out are 0 "
                                                                 "(the mean body)")->type_name("C1,C2,...");
    CLI::Option* pose = c->add_option("--pose", o->pose,
                  "a named pose (a_pose = rest, t_pose, sitting, arms_raised, crouching, kneeling, bending_forward, "
                  "bent_over_arms_raised, lunge, arms_behind_back), then joint rotations as axis * angle in radians, "
                  "separated by ';': \"sitting;head=0.3,0,0\" (sscape info lists the joints)")
        ->type_name("POSE");
    c->add_option("--hands", o->hands, "close the hands: 0 open (the model's), 1 a loose fist; one value for both hands or LEFT,RIGHT")
        ->type_name("C|LEFT,RIGHT")->delimiter(',')->expected(1, 2)->check(finite_in(0, 1));
    CLI::Option* translation = c->add_option("--translation", o->translation_text, "where the root goes, in metres")->type_name("X,Y,Z");
    CLI::Option* random = c->add_option("--random", o->random, "write N random shapes (coefficients standard normal, truncated at 2.5 SD)")
                              ->check(CLI::Range(1u, 10000u))->type_name("N");
    c->add_option("--seed", o->seed, "random seed for --random")->capture_default_str();
    CLI::Option* sliders = c->add_option("--sliders", o->sliders_text, "set semantic sliders (SI units; sscape info lists them with their "
                                                                       "population ranges): stature=1.85,mass=80")
                               ->type_name("NAME=VALUE,...");
    CLI::Option* measure = c->add_option("--measure", o->measure_text,
                                         "make the body to measure (SI units; sscape measure --definitions lists the measurements): "
                                         "stature=1.7,waist_girth=0.8")
                               ->type_name("NAME=VALUE,...");
    c->add_option("--sex", o->sex_text, "with --measure: the sex the body is made for")
        ->check(CLI::IsMember({"female", "male"}).description(""))->type_name("female|male");
    c->add_option("--age", o->age, "with --measure: the age the body is made for, in years")->check(finite_in(0, 120))->type_name("YEARS");
    c->add_option("--limits", o->limits, "joint rotations beyond the model's anatomical limits: clamp them, or reject the pose "
                                         "(default: neither)")
        ->check(CLI::IsMember({"clamp", "reject"}).description(""))->type_name("clamp|reject");
    c->add_option("--params", o->params, "the shape, pose and translation of a fit, as sscape fit --params wrote them")
        ->type_name("FIT.json")->excludes(shape)->excludes(pose)->excludes(translation)->excludes(random)->excludes(sliders)->excludes(measure);
    c->add_option("--png", o->png, "draw front and side views of the bodies (up to 20)")->type_name("OUT.png")->check(extension(".png"));
    c->add_option("--landmarks-png", o->landmarks_png, "draw the first body's landmarks: front, back, side, head and trunk close up")
        ->type_name("OUT.png")->check(extension(".png"));
    c->add_option("--segment", o->segment_texts, "segment shape coefficients (standard deviations) on top of the whole-body shape, "
                  "for models with segment shape spaces (sscape info lists them)")
        ->type_name("NAME=C1,C2,...");
    c->add_option("--lod", o->lod, "the level of detail to write, by number or name (0 or full: the whole mesh; sscape info lists "
                                   "the model's); all: every level in one .glb, a node each")->type_name("LEVEL")->capture_default_str();
    c->add_option("--morphs", o->morphs, "shape morph targets in the .glb, so an engine varies the body without the library: K (the "
                  "first K shape components, weight 1 = +1 SD) or sliders (the semantic sliders, weight 1 = +1 SD of the attribute); "
                  "the joints' motion per unit of weight goes into the file's extras (docs/engines.md)")->type_name("K|sliders");
    c->add_flag("--normals", o->normals, "kept for old scripts: normals are always written");
    random->excludes(shape)->excludes(sliders)->excludes(measure);
    return [o] { return run_synth(*o); };
}

}  // namespace ssc::cli
