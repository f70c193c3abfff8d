#include "proxy.hpp"

#include "assets.hpp"
#include "common/error.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ssc::training::mh {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad(const std::string& path, std::size_t line, const std::string& what) {
    fail(SSC_ERROR_IO, "'" + path + "' line " + std::to_string(line) + ": " + what);
}

// The proxy's .obj: vertices are the proxy's (counted only), faces with texture coordinates.
void read_proxy_obj(const std::string& path, Proxy& p) {
    std::ifstream in(path);
    if (!in) fail(SSC_ERROR_IO, "cannot open '" + path + "'");
    std::string line;
    std::size_t n = 0, vertices = 0;
    while (std::getline(in, line)) {
        ++n;
        std::istringstream s(line);
        std::string tag;
        if (!(s >> tag)) continue;
        if (tag == "v") {
            ++vertices;
        } else if (tag == "vt") {
            float u = 0, v = 0;
            if (!(s >> u >> v) || !std::isfinite(u) || !std::isfinite(v)) bad(path, n, "a texture coordinate needs two numbers");
            p.uvs.push_back(u), p.uvs.push_back(v);
        } else if (tag == "f") {
            std::vector<uint32_t> corner, uv;
            std::string c;
            while (s >> c) {
                const std::size_t slash = c.find('/');
                if (slash == std::string::npos) bad(path, n, "a face corner needs a texture coordinate (v/vt)");
                try {
                    const long vi = std::stol(c.substr(0, slash)), ti = std::stol(c.substr(slash + 1));
                    if (vi < 1 || ti < 1) bad(path, n, "face indices start at 1");
                    corner.push_back(uint32_t(vi - 1)), uv.push_back(uint32_t(ti - 1));
                } catch (const std::logic_error&) {
                    bad(path, n, "a face corner is not v/vt");
                }
            }
            if (corner.size() < 3 || corner.size() > 4) bad(path, n, "faces must be triangles or quads");
            for (std::size_t k : corner.size() == 3 ? std::vector<std::size_t>{0, 1, 2} : std::vector<std::size_t>{0, 1, 2, 0, 2, 3})
                p.triangles.push_back(corner[k]), p.triangle_uvs.push_back(uv[k]);
        }
    }
    if (vertices != p.refs.size())
        fail(SSC_ERROR_IO, "'" + path + "' has " + std::to_string(vertices) + " vertices, its proxy binds " + std::to_string(p.refs.size()));
    for (std::size_t i = 0; i < p.triangles.size(); ++i)
        if (p.triangles[i] >= vertices || p.triangle_uvs[i] >= p.uvs.size() / 2) fail(SSC_ERROR_IO, "'" + path + "': a face index is out of range");
}

}  // namespace

Proxy read_proxy(const std::string& proxy_path, uint32_t base_vertex_count) {
    std::ifstream in(proxy_path);
    if (!in) fail(SSC_ERROR_IO, "cannot open '" + proxy_path + "'");
    Proxy p;
    std::string line, obj;
    std::size_t n = 0;
    bool in_verts = false;
    int scales = 0;
    while (std::getline(in, line)) {
        ++n;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        if (in_verts) {
            // A binding is 1 or 9 numbers; the list ends at a line that starts with a word.
            std::vector<std::string> tokens;
            for (std::string t; s >> t;) tokens.push_back(t);
            const auto number = [](const std::string& t, double& out) {
                char* end = nullptr;
                out = std::strtod(t.c_str(), &end);
                return end == t.c_str() + t.size() && std::isfinite(out);
            };
            std::vector<double> x(tokens.size());
            bool numeric = !tokens.empty() && (std::isdigit(static_cast<unsigned char>(tokens[0][0])) || tokens[0][0] == '-' || tokens[0][0] == '.');
            for (std::size_t k = 0; numeric && k < tokens.size(); ++k)
                if (!number(tokens[k], x[k])) bad(proxy_path, n, "'" + tokens[k] + "' is not a finite number");
            if (numeric && x.size() != 1 && x.size() != 9) bad(proxy_path, n, "a binding is one base vertex or 9 numbers (3 vertices, 3 weights, 3 offsets)");
            if (numeric) {
                std::array<uint32_t, 3> r{};
                for (std::size_t k = 0; k < 3; ++k) {
                    const double idx = x[x.size() == 1 ? 0 : k];
                    if (idx < 0 || idx >= base_vertex_count || idx != std::floor(idx)) bad(proxy_path, n, "a base vertex index is out of range");
                    r[k] = uint32_t(idx);
                }
                std::array<float, 3> w{1, 0, 0}, d{0, 0, 0};
                if (x.size() == 9)
                    for (std::size_t k = 0; k < 3; ++k) w[k] = float(x[3 + k]), d[k] = float(x[6 + k]);
                for (std::size_t k = 0; k < 3; ++k)
                    if (!std::isfinite(w[k]) || !std::isfinite(d[k]) || std::abs(w[k]) > 8 || std::abs(d[k]) > 10) bad(proxy_path, n, "a weight or offset is out of range");
                p.refs.push_back(r), p.weights.push_back(w), p.offsets.push_back(d);
                continue;
            }
            in_verts = false;
            s.clear(), s.str(line);
        }
        std::string key;
        s >> key;
        if (key == "name") {
            s >> p.name;
        } else if (key == "obj_file") {
            s >> obj;
        } else if (key == "x_scale" || key == "y_scale" || key == "z_scale") {
            const std::size_t axis = std::size_t(key[0] - 'x');
            double a = -1, b = -1, length = 0;
            if (!(s >> a >> b >> length) || a < 0 || b < 0 || a >= base_vertex_count || b >= base_vertex_count || !(length > 0))
                bad(proxy_path, n, "a scale needs two base vertices and a length > 0");
            p.scale_a[axis] = uint32_t(a), p.scale_b[axis] = uint32_t(b), p.scale_length[axis] = float(length);
            ++scales;
        } else if (key == "verts") {
            in_verts = true;
        }
    }
    if (p.refs.empty()) fail(SSC_ERROR_IO, "'" + proxy_path + "' binds no vertices");
    if (scales != 3) fail(SSC_ERROR_IO, "'" + proxy_path + "' needs x_scale, y_scale and z_scale");
    if (obj.empty()) fail(SSC_ERROR_IO, "'" + proxy_path + "' names no obj_file");
    if (p.name.empty()) p.name = fs::path(proxy_path).stem().string();
    read_proxy_obj((fs::path(proxy_path).parent_path() / obj).string(), p);
    return p;
}

std::vector<std::array<double, 3>> proxy_positions(const Proxy& proxy, const std::vector<float>& base_xyz) {
    std::array<double, 3> scale{};
    for (std::size_t a = 0; a < 3; ++a)
        scale[a] = std::abs(double(base_xyz[3 * std::size_t(proxy.scale_a[a]) + a]) - base_xyz[3 * std::size_t(proxy.scale_b[a]) + a]) /
                   (double(proxy.scale_length[a]) * kUnitToMetres);
    std::vector<std::array<double, 3>> out(proxy.refs.size());
    for (std::size_t i = 0; i < proxy.refs.size(); ++i)
        for (std::size_t a = 0; a < 3; ++a) {
            double x = scale[a] * proxy.offsets[i][a] * kUnitToMetres;
            for (std::size_t k = 0; k < 3; ++k) x += proxy.weights[i][k] * base_xyz[3 * std::size_t(proxy.refs[i][k]) + a];
            out[i][a] = x;
        }
    return out;
}

}  // namespace ssc::training::mh
