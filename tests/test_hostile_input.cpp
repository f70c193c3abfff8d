// Regressions for defects found by probing the library as an attacker would (issue 19): bodies far
// outside the population, huge and inconsistent file content, special files, planted links. Each
// case failed (crashed, hung, read out of bounds, returned nonsense or wrote through a link) before.
#include "support.hpp"

#include "common/files.hpp"
#include "io/readers.hpp"
#include "measure/girth.hpp"
#include "measure/measurements.hpp"
#include "sscape_format/model_io.hpp"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

extern "C" {
extern const unsigned char ssc_internal_default_model[];
extern const unsigned char ssc_internal_default_model_end[];
}

namespace fs = std::filesystem;

namespace {

template <class F>
ssc::Error error_of(F&& f) {
    try {
        f();
    } catch (const ssc::Error& e) {
        return e;
    }
    return ssc::Error(SSC_OK, "");
}

std::string last_error() { return ssc_last_error(); }

ssc::format::ModelData default_data() {
    return ssc::format::read_model(ssc_internal_default_model,
                                   std::size_t(ssc_internal_default_model_end - ssc_internal_default_model));
}

// A fresh, empty folder for file tests.
fs::path scratch(const std::string& name) {
    const fs::path dir = fs::current_path() / ("hostile_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST_CASE("measuring a body far outside the population is refused, not cut at thousands of levels", "[hostile][measure]") {
    // A model file whose (finite) mean is 1e4 times a person: verified and loaded, but not measurable.
    auto data = default_data();
    for (float& x : data.shape.mean) x *= 1e4f;
    const auto model = test::load(ssc::format::write_model(data));
    REQUIRE(model);
    const auto body = test::body(model.get());
    std::vector<float> out(ssc_measurement_count(), -1.f);
    CHECK(ssc_body_measure(body.get(), out.data(), uint32_t(out.size())) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(last_error(), Catch::Contains("measurements are defined for bodies within 5 m"));
    CHECK(out[0] == -1.f);  // nothing written

    // The default model at the edge of the accepted shapes is measured or refused, never more.
    test::DefaultBody b;
    std::vector<float> extreme(ssc_model_shape_count(b.model), SSC_SHAPE_COEFFICIENT_LIMIT);
    REQUIRE(ssc_body_set_shape(b.body, extreme.data(), uint32_t(extreme.size())) == SSC_OK);
    const ssc_status s = ssc_body_measure(b.body, out.data(), uint32_t(out.size()));
    CHECK((s == SSC_OK || s == SSC_ERROR_INVALID_ARGUMENT));
}

TEST_CASE("the level sweep clamps far-away edges before converting to int", "[hostile][measure]") {
    // Edges 1e30 m away used to overflow the level index (undefined behaviour; girth 0 in Release).
    const float xyz[] = {0, 1e30f, 0, 0, -1e30f, 0, 1, 0.5f, 0, 1, -0.5f, 0, 0, std::nanf(""), 0};
    const std::vector<uint32_t> edges = {0, 1, 2, 3, 0, 4};
    const auto sections = ssc::measure::horizontal_sections(xyz, edges, 0.2, 0.1, 5);
    REQUIRE(sections.size() == 5);
    for (const auto& s : sections) CHECK(s.size() == 2);  // each level crosses the two finite edges
}

TEST_CASE("shape coefficients and slider values outside their documented ranges are refused", "[hostile][semantics]") {
    test::DefaultBody b;
    const uint32_t K = ssc_model_shape_count(b.model);
    std::vector<float> before(K), after(K);
    const float start[2] = {0.5f, -0.25f};
    REQUIRE(ssc_body_set_shape(b.body, start, 2) == SSC_OK);
    REQUIRE(ssc_body_get_shape(b.body, before.data(), K) == SSC_OK);

    const float huge = 1e9f;
    CHECK(ssc_body_set_shape(b.body, &huge, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(last_error(), Catch::Contains("within +-20 standard deviations"));
    const float edge = SSC_SHAPE_COEFFICIENT_LIMIT, beyond = std::nextafter(SSC_SHAPE_COEFFICIENT_LIMIT, 100.f);
    CHECK(ssc_body_set_shape(b.body, &beyond, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_shape(b.body, &edge, 1) == SSC_OK);
    REQUIRE(ssc_body_set_shape(b.body, start, 2) == SSC_OK);

    uint32_t stature = 0;
    REQUIRE(ssc_model_find_slider(b.model, "stature", &stature) == SSC_OK);
    // 3e38 is finite as a float, but the shape it asks for is not.
    CHECK(ssc_body_set_slider(b.body, stature, 3e38f) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(last_error(), Catch::Contains("outside the accepted range"));
    CHECK(ssc_body_set_slider(b.body, stature, 1e30f) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_slider(b.body, stature, -1.f) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_body_get_shape(b.body, after.data(), K) == SSC_OK);
    CHECK(after == before);  // unchanged by the refused calls
    CHECK(ssc_body_set_slider(b.body, stature, 2.2f) == SSC_OK);  // beyond the population, within the accepted range

    std::vector<float> values(ssc_model_slider_count(b.model));
    REQUIRE(ssc_body_get_sliders(b.body, values.data(), uint32_t(values.size())) == SSC_OK);
    values[stature] = 3e38f;
    CHECK(ssc_body_set_sliders(b.body, values.data(), uint32_t(values.size())) == SSC_ERROR_INVALID_ARGUMENT);

    // Made to measure: an absurd target is refused with the range; a plausible one works.
    uint32_t m_stature = 0;
    REQUIRE(ssc_measurement_find("stature", &m_stature) == SSC_OK);
    const float absurd = 1e30f;
    CHECK(ssc_body_make_to_measure(b.body, &m_stature, &absurd, 1, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(last_error(), Catch::Contains("accepted range"));
    uint32_t m_thigh = 0;
    REQUIRE(ssc_measurement_find("thigh_girth", &m_thigh) == SSC_OK);
    const float ten_metres = 10.f;
    CHECK(ssc_body_make_to_measure(b.body, &m_thigh, &ten_metres, 1, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);

    // Batches take the same range.
    std::vector<float> vertices(3ull * ssc_model_vertex_count(b.model));
    ssc_batch_desc desc;
    ssc_batch_desc_init(&desc, sizeof desc);
    desc.body_count = 1;
    desc.shapes = &huge;
    desc.shape_count = 1;
    desc.vertices = vertices.data();
    desc.vertices_capacity = ssc_model_vertex_count(b.model);
    CHECK(ssc_model_synthesize_batch(b.model, &desc) == SSC_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("point readers return one normal per point or none", "[hostile][io]") {
    // Two vertex elements, one with normals: fewer normals than points used to reach the fitter.
    const std::string two_vertex_elements =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0\n1 1 0\n";
    const auto e = error_of([&] { ssc::io::parse_ply(two_vertex_elements, "two.ply"); });
    CHECK(e.status() == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(std::string(e.what()), Catch::Contains("more than one 'vertex' element"));

    // Finite but huge coordinates: normals from faces are finite unit vectors (they were NaN).
    const auto obj = ssc::io::parse_obj("v 0 1e308 0\nv -1e308 -1e308 0\nv 1e308 -1e308 0\nf 1 2 3\n", "huge.obj");
    REQUIRE(obj.normals.size() == 3);
    for (const auto& n : obj.normals) {
        CHECK(n.allFinite());
        CHECK(std::abs(n.norm() - 1) < 1e-12);
    }
    const auto ply = ssc::io::parse_ply(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "property double nx\nproperty double ny\nproperty double nz\nend_header\n"
        "0 1e308 0 1e308 1e308 0\n-1e308 -1e308 0 0 0 1\n1e308 -1e308 0 0 0 1\n",
        "huge.ply");
    REQUIRE(ply.normals.size() == 3);
    CHECK(ply.normals[0].allFinite());
    CHECK(std::abs(ply.normals[0].norm() - 1) < 1e-12);
    // A normal that cannot be normalised (zero length, common in real scans) is unknown (zero): the
    // fitter estimates it; the usable ones are kept.
    const auto zero_normals = ssc::io::parse_obj("v 0 0 0\nv 1 0 0\nvn 0 0 0\nvn 0 0 2\n", "zero.obj");
    CHECK(zero_normals.points.size() == 2);
    REQUIRE(zero_normals.normals.size() == 2);
    CHECK(zero_normals.normals[0] == Eigen::Vector3d::Zero());
    CHECK(zero_normals.normals[1] == Eigen::Vector3d::UnitZ());
    const auto ply_zero = ssc::io::parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                             "property float nx\nproperty float ny\nproperty float nz\nend_header\n"
                                             "0 0 0 0 0 0\n1 0 0 0 0 0\n0 1 0 3 0 0\n", "zero.ply");
    REQUIRE(ply_zero.normals.size() == 3);
    CHECK(ply_zero.normals[0] == Eigen::Vector3d::Zero());
    CHECK(ply_zero.normals[1] == Eigen::Vector3d::Zero());
    CHECK(ply_zero.normals[2] == Eigen::Vector3d::UnitX());
    // None usable: none at all.
    CHECK(ssc::io::parse_obj("v 0 0 0\nv 1 0 0\nvn 0 0 0\nvn 0 0 0\n", "none.obj").normals.empty());
}

TEST_CASE("a PLY element without properties is skipped, not looped over", "[hostile][io]") {
    // A million entries of nothing in a 1 MB file: read at once, then the megabyte left over is refused.
    std::string file = "ply\nformat binary_little_endian 1.0\nelement junk 1000000\nelement vertex 0\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n";
    file.resize(file.size() + 1000000, '\0');
    const auto e = error_of([&] { ssc::io::parse_ply(file, "junk.ply"); });
    CHECK(e.status() == SSC_ERROR_INVALID_ARGUMENT);
    CHECK_THAT(std::string(e.what()), Catch::Contains("1000000 bytes follow the elements the header declares"));
}

TEST_CASE("a model without the measurement landmarks fails the same way every time, from any thread", "[hostile][measure]") {
    const auto model = test::load(test::mini_bytes());
    REQUIRE(model);
    std::vector<std::string> messages(4);
    std::vector<ssc_status> status(4);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            const auto body = test::body(model.get());
            std::vector<float> out(ssc_measurement_count());
            status[std::size_t(t)] = ssc_body_measure(body.get(), out.data(), uint32_t(out.size()));
            messages[std::size_t(t)] = ssc_last_error();
        });
    for (auto& t : threads) t.join();
    for (int t = 0; t < 4; ++t) {
        CHECK(status[std::size_t(t)] == SSC_ERROR_NOT_FOUND);
        CHECK_THAT(messages[std::size_t(t)], Catch::Contains("measurements need the landmark"));
    }
}

TEST_CASE("model loading opens regular files only", "[hostile][format]") {
    const fs::path dir = scratch("special");
    ssc_model* m = nullptr;
    CHECK(ssc_model_load_file(nullptr, dir.c_str(), &m) == SSC_ERROR_IO);
    CHECK_THAT(last_error(), Catch::Contains("is a directory"));
    const fs::path fifo = dir / "model.fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK(ssc_model_load_file(nullptr, fifo.c_str(), &m) == SSC_ERROR_IO);  // used to block forever
    CHECK_THAT(last_error(), Catch::Contains("not a regular file"));
    CHECK(m == nullptr);
    const auto e = error_of([&] { ssc::io::read_points(fifo.string() + ".ply"); });
    CHECK(e.status() == SSC_ERROR_IO);
}

TEST_CASE("ssc_model_get_skin accepts NULL for both outputs, as documented", "[hostile][capi]") {
    test::DefaultBody b;
    CHECK(ssc_model_get_skin(b.model, nullptr, nullptr, ssc_model_vertex_count(b.model)) == SSC_OK);
    std::vector<float> weights(4ull * ssc_model_vertex_count(b.model));
    CHECK(ssc_model_get_skin(b.model, nullptr, weights.data(), ssc_model_vertex_count(b.model)) == SSC_OK);
    CHECK(ssc_model_get_skin(b.model, nullptr, weights.data(), 1) == SSC_ERROR_BUFFER_TOO_SMALL);
}

TEST_CASE("atomic writes never follow a planted link and leave no temporary behind", "[hostile][files]") {
    const fs::path dir = scratch("atomic");
    const fs::path victim = dir / "victim.txt", target = dir / "out.obj";
    { std::ofstream(victim) << "precious"; }
    // The old fixed temporary name, planted as a link to someone else's file.
    fs::create_symlink(victim, dir / "out.obj.tmp");
    ssc::write_file_atomically(target.string(), "body", 4);
    CHECK(slurp(target) == "body");
    CHECK(slurp(victim) == "precious");
    // The target itself a link: the link is replaced, the file it pointed at is not written.
    const fs::path link = dir / "link.obj";
    fs::create_symlink(victim, link);
    ssc::write_file_atomically(link.string(), "new", 3);
    CHECK(!fs::is_symlink(link));
    CHECK(slurp(link) == "new");
    CHECK(slurp(victim) == "precious");
    // The new file gets the usual permissions (0666 less the umask), not a temporary's 0600.
    const mode_t mask = ::umask(0022);
    ::umask(mask);
    CHECK((fs::status(target).permissions() & fs::perms::all) == fs::perms(0666 & ~mask));
    // Nothing else appeared: no temporary survives.
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    CHECK(names == std::vector<std::string>{"link.obj", "out.obj", "out.obj.tmp", "victim.txt"});
    // A folder that does not exist: an I/O error, and nothing written.
    const auto e = error_of([&] { ssc::write_file_atomically((dir / "missing" / "x.obj").string(), "x", 1); });
    CHECK(e.status() == SSC_ERROR_IO);
    CHECK(!fs::exists(dir / "missing"));
}
