// Measurement file readers: well-formed files read back, malformed and hostile ones refused with
// a message naming the file, never a crash.
#include "common/error.hpp"
#include "common/files.hpp"
#include "io/readers.hpp"
#include "support.hpp"
#include "io/writers.hpp"
#include "render/plot.hpp"
#include "render/text.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

using namespace ssc;

namespace {

std::string temp_file(const std::string& name, const std::string& content) {
    const std::string path = "io_test_" + name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
}

template <class F>
ssc_status status_of(F&& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.status();
    }
    return SSC_OK;
}

}  // namespace

TEST_CASE("lnd files round-trip and skip missing landmarks", "[io]") {
    std::vector<io::LandmarkRecord> in = {{1, "Sellion", Eigen::Vector3d(0.01, 1.6, 0.1)}, {12, "Lt. Clavicale", Eigen::Vector3d(0.1, 1.4, 0)}};
    io::write_lnd("io_test_a.lnd", "subject 1", in);
    const auto out = io::read_lnd("io_test_a.lnd");
    REQUIRE(out.size() == 2);
    CHECK(out[1].name == "Lt. Clavicale");
    CHECK(out[1].index == 12);
    CHECK((out[0].position - in[0].position).norm() < 1e-5);
    // The documented row shape, with a not-found landmark and CRLF line ends.
    const auto path = temp_file("b.lnd", "SUBJECT_ID = x\r\nAUX =\r\n12   0  12  105.10   99.16   -2.63  326.00 Lt. Clavicale\r\n"
                                         " 3 -999 -999 0 0 0 0 Lt. Infraorbitale\r\nEND =\r\n");
    const auto b = io::read_lnd(path);
    REQUIRE(b.size() == 1);
    CHECK(b[0].position.isApprox(Eigen::Vector3d(0.09916, -0.00263, 0.326)));
    CHECK(io::normalized_landmark_name("Lt. Metacarpal-Phal. II") == io::normalized_landmark_name("lt metacarpal phal ii"));
    CHECK(status_of([&] { io::read_lnd(temp_file("c.lnd", "AUX =\n1 0 1 0 1 2 3 Sellion\n")); }) == SSC_ERROR_INVALID_ARGUMENT);  // no END
    CHECK(status_of([&] { io::read_lnd(temp_file("d.lnd", "AUX =\n1 0 1 zero 1 2 3 Sellion\nEND =\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_lnd("io_test_missing.lnd"); }) == SSC_ERROR_IO);
}

TEST_CASE("an lnd file naming one landmark twice is refused with both lines", "[io]") {
    // Spelt differently, 300 mm apart: two positions for one point, which no rule can choose between.
    const std::string twice = "AUX =\n1 0 1 0 10 1600 100 Sellion\n2 0 1 0 10 1300 100 Lt. Clavicale\n3 0 1 0 10 1900 100 SELLION\nEND =\n";
    std::string message;
    CHECK(status_of([&] { io::parse_lnd(twice, "twice.lnd"); }, &message) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(message.find("twice.lnd") != std::string::npos);
    CHECK(message.find("line 4") != std::string::npos);
    CHECK(message.find("first on line 2") != std::string::npos);
    // Even when one of the two is marked not found: the file contradicts itself.
    CHECK(status_of([&] { io::parse_lnd("AUX =\n1 0 1 0 1 2 3 Sellion\n2 -999 -999 0 0 0 0 Sellion\nEND =\n", "x.lnd"); }) ==
          SSC_ERROR_INVALID_ARGUMENT);
    CHECK(io::parse_lnd("AUX =\n1 0 1 0 1 2 3 Sellion\n2 0 1 0 1 2 3 Lt. Clavicale\nEND =\n", "ok.lnd").size() == 2);
}

TEST_CASE("a PLY header that under-counts its vertices is refused instead of reading part of the scan", "[io]") {
    // 5 vertices declared over 20 stored: once the first 5 were read and 15 ignored without a word.
    const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex ";
    const std::string props = "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    std::vector<float> xyz(60);
    for (std::size_t i = 0; i < xyz.size(); ++i) xyz[i] = float(i) * 0.01f;
    const std::string data(reinterpret_cast<const char*>(xyz.data()), xyz.size() * sizeof(float));
    std::string message;
    CHECK(status_of([&] { io::parse_ply(head + "5" + props + data, "under.ply"); }, &message) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(message.find("180 bytes follow the elements the header declares (5 vertices)") != std::string::npos);
    CHECK(io::parse_ply(head + "20" + props + data, "whole.ply").points.size() == 20);
    CHECK(io::parse_ply(head + "20" + props + data + "\n", "newline.ply").points.size() == 20);  // a final newline is no data
    // The same in ASCII; trailing blank lines are fine.
    const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                              "0 0 0\n1 0 0\n";
    CHECK(io::parse_ply(ascii + "\n  \n", "blank.ply").points.size() == 2);
    CHECK(status_of([&] { io::parse_ply(ascii + "0 1 0\n", "more.ply"); }, &message) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(message.find("the header under-counts them") != std::string::npos);
}

TEST_CASE("PLY and OBJ point files read, with normals from faces", "[io]") {
    const auto ply = temp_file("a.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const auto a = io::read_points(ply);
    REQUIRE(a.points.size() == 3);
    REQUIRE(a.normals.size() == 3);
    CHECK(a.normals[0].isApprox(Eigen::Vector3d(0, 0, 1)));
    const auto obj = temp_file("a.obj", "# c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto b = io::read_points(obj);
    REQUIRE(b.points.size() == 3);
    CHECK(b.normals[2].isApprox(Eigen::Vector3d(0, 0, 1)));
    // Binary little endian with normals.
    std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
    const float v[12] = {1, 2, 3, 0, 0, 1, 4, 5, 6, 1, 0, 0};
    bin.append(reinterpret_cast<const char*>(v), sizeof v);
    const auto c = io::read_points(temp_file("b.ply", bin));
    REQUIRE(c.points.size() == 2);
    CHECK(c.points[1].isApprox(Eigen::Vector3d(4, 5, 6)));
    CHECK(c.normals[1].isApprox(Eigen::Vector3d(1, 0, 0)));
    // Truncated at every byte: an error, never a crash.
    for (std::size_t n = 0; n < bin.size(); ++n) {
        const auto path = temp_file("t.ply", bin.substr(0, n));
        CHECK(status_of([&] { io::read_points(path); }) != SSC_OK);
    }
    // Hostile count and bad face index.
    CHECK(status_of([&] {
              io::read_points(temp_file("h.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                                 "property float y\nproperty float z\nend_header\n"));
          }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_points(temp_file("f.obj", "v 0 0 0\nf 1 2 3\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_points(temp_file("n.obj", "v 0 nan 0\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_points(temp_file("x.xyz", "0 0 0\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_points(temp_file("s.obj", "v 0 1.5x 0\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_points(temp_file("w.obj", "v 0 0 0\nvn 0 1\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("NaN normals are unknown normals in OBJ as in PLY: one rule for both formats", "[io]") {
    // The same two points, the first with a NaN normal (as real scanners write them): read from
    // either format they give the same points and normals, the unknown one zero.
    const auto ply = io::read_points(temp_file("nan.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                                          "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n"
                                                          "0 0 0 nan nan nan\n1 0 0 0 0 1\n"));
    const auto obj = io::read_points(temp_file("nan.obj", "v 0 0 0\nv 1 0 0\nvn nan nan nan\nvn 0 0 1\n"));
    REQUIRE(ply.normals.size() == 2);
    REQUIRE(obj.normals.size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        CHECK(ply.points[i] == obj.points[i]);
        CHECK(ply.normals[i] == obj.normals[i]);
    }
    CHECK(obj.normals[0] == Eigen::Vector3d::Zero());
    CHECK(obj.normals[1] == Eigen::Vector3d(0, 0, 1));
}

TEST_CASE("16-bit PGM depth images read in metres", "[io]") {
    std::string pgm = "P5\n# depth\n3 2\n65535\n";
    const unsigned char px[12] = {0x03, 0xE8, 0, 0, 0x07, 0xD0, 0, 1, 0, 2, 0xFF, 0xFF};  // 1000 mm, 0, 2000 mm, ...
    pgm.append(reinterpret_cast<const char*>(px), sizeof px);
    const auto img = io::read_pgm_depth(temp_file("a.pgm", pgm));
    REQUIRE(img.width == 3);
    REQUIRE(img.height == 2);
    CHECK(img.depth[0] == Approx(1.0f));
    CHECK(img.depth[1] == 0.f);
    CHECK(img.depth[2] == Approx(2.0f));
    CHECK(img.depth[5] == Approx(65.535f));
    CHECK(status_of([&] { io::read_pgm_depth(temp_file("b.pgm", pgm.substr(0, pgm.size() - 1))); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_pgm_depth(temp_file("c.pgm", "P5\n3 2\n255\n123456")); }) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of([&] { io::read_pgm_depth(temp_file("d.pgm", "P2\n3 2\n65535\n")); }) == SSC_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("PGM depth images keep their camera through write and read", "[io]") {
    io::DepthImage img;
    img.width = 4, img.height = 3;
    img.depth = {1.0f, 0.f, 2.5f, 0.0004f, 1.2345f, 70.f, std::nanf(""), 3.f, 0.5f, 0.5f, 0.5f, 0.5f};
    img.has_intrinsics = img.has_pose = true;
    img.fx = 525, img.fy = 524.5, img.cx = 1.5, img.cy = 1;
    img.camera_to_world.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    img.camera_to_world.topRightCorner<3, 1>() = Eigen::Vector3d(0.1, 1.2, 2.8);
    const std::string path = temp_file("cam.pgm", "");
    io::write_pgm_depth(path, img);
    const auto back = io::read_pgm_depth(path);
    REQUIRE(back.width == 4);
    REQUIRE(back.height == 3);
    CHECK(back.depth[0] == Approx(1.0f));
    CHECK(back.depth[2] == Approx(2.5f));
    CHECK(back.depth[3] == 0.f);                       // below half a millimetre
    CHECK(back.depth[4] == Approx(1.235f).margin(1e-6));  // rounded to millimetres
    CHECK(back.depth[5] == 0.f);                       // beyond 65.535 m
    CHECK(back.depth[6] == 0.f);                       // NaN: no reading
    REQUIRE(back.has_intrinsics);
    REQUIRE(back.has_pose);
    CHECK(back.fy == 524.5);
    CHECK(back.cx == 1.5);
    CHECK((back.camera_to_world - img.camera_to_world).norm() < 1e-12);
    std::string bad = "P5\n# sscape intrinsics 525 525 x 3\n2 2\n65535\n";
    bad.append(8, '\0');
    CHECK(status_of([&] { io::read_pgm_depth(temp_file("e.pgm", bad)); }) == SSC_ERROR_INVALID_ARGUMENT);
    std::string other = "P5\n# made by another tool 1 2 3\n2 2\n65535\n";
    other.append(8, '\0');
    CHECK_FALSE(io::read_pgm_depth(temp_file("g.pgm", other)).has_intrinsics);
}

TEST_CASE("the C API writes a body as OBJ, PLY and rigged glTF that read back as the body", "[io][capi]") {
    test::DefaultBody d;
    const float shape[3] = {1.0f, -0.5f, 0.25f};
    REQUIRE(ssc_body_set_shape(d.body, shape, 3) == SSC_OK);
    std::vector<float> pose(4 * std::size_t(ssc_model_joint_count(d.model)));
    REQUIRE(ssc_model_get_named_pose(d.model, "sitting", pose.data(), ssc_model_joint_count(d.model)) == SSC_OK);
    const float translation[3] = {0.1f, 0.0f, -0.2f};
    REQUIRE(ssc_body_set_pose(d.body, pose.data(), ssc_model_joint_count(d.model), translation) == SSC_OK);
    const auto want = test::posed(d.model, d.body);
    for (const char* path : {"io_body.obj", "io_body.PLY"}) {
        INFO(path);
        REQUIRE(ssc_body_write_file(d.body, path, SSC_FILE_FORMAT_BY_EXTENSION) == SSC_OK);
        const auto read = io::read_points(path);
        REQUIRE(read.points.size() == want.size() / 3);
        double worst = 0;
        for (std::size_t v = 0; v < read.points.size(); ++v)
            worst = std::max(worst, (read.points[v] - Eigen::Vector3d(want[3 * v], want[3 * v + 1], want[3 * v + 2])).norm());
        CHECK(worst < 1e-5);  // OBJ's text keeps 6 significant digits or more
        CHECK(read.normals.size() == read.points.size());
    }
    REQUIRE(ssc_body_write_file(d.body, "io_body.bin", SSC_FILE_GLB) == SSC_OK);  // the format given, not the extension
    const std::string glb = ssc::read_regular_file("io_body.bin", 64u << 20);
    REQUIRE(glb.size() > 12);
    CHECK(glb.compare(0, 4, "glTF") == 0);
    // Bad input: an error and a message, no file.
    CHECK(ssc_body_write_file(d.body, "io_body.fbx", SSC_FILE_FORMAT_BY_EXTENSION) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find(".glb") != std::string::npos);
    CHECK(ssc_body_write_file(d.body, "io_body.obj", static_cast<ssc_file_format>(7)) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_write_file(d.body, nullptr, SSC_FILE_OBJ) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_write_file(nullptr, "io_body.obj", SSC_FILE_OBJ) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_write_file(d.body, "no-such-dir/io_body.obj", SSC_FILE_OBJ) == SSC_ERROR_IO);
}

TEST_CASE("pictures carry text and plots: the built-in font and the line plot", "[render]") {
    // "1" at scale 2: the stem is the glyph's middle column, two pixels wide, seven glyph rows high.
    render::Image img(20, 20);
    const uint8_t black[3] = {0, 0, 0};
    render::draw_text(img, 0, 0, "1", 2, black);
    auto dark = [&](int x, int y) { return img.rgb[(std::size_t(y) * img.width + x) * 3] == 0; };
    for (int y = 0; y < 14; ++y) CHECK((dark(4, y) && dark(5, y)));
    CHECK_FALSE(dark(0, 6));  // left of the stem, mid-height
    CHECK(render::text_width("ab", 2) == 22);

    render::LinePlot plot{"compactness", "number of components", "explained", {1, 2, 5, 10}, {0.5, 0.8, 0.95, 0.99}, {}, {}};
    const std::string path = "io_test_plot.png";
    std::remove(path.c_str());
#if SSCAPE_WITH_PNG
    render::write_line_plot(path, plot);
    std::ifstream f(path, std::ios::binary);
    char signature[8] = {};
    f.read(signature, 8);
    CHECK(std::string(signature + 1, 3) == "PNG");
#endif
    plot.y.pop_back();
    CHECK(status_of([&] { render::write_line_plot(path + "x", plot); }) == SSC_ERROR_INVALID_ARGUMENT);
    plot.y.push_back(std::nan(""));
    CHECK(status_of([&] { render::write_line_plot(path + "x", plot); }) == SSC_ERROR_INVALID_ARGUMENT);
}
