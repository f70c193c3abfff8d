#include "io/readers.hpp"

#include "common/error.hpp"
#include "common/files.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <sstream>
#include <unordered_map>

namespace ssc::io {

namespace {

std::string slurp(const std::string& path) { return read_regular_file(path, kMaxInputBytes); }

[[noreturn]] void bad(const std::string& path, const std::string& what) { fail(SSC_ERROR_INVALID_ARGUMENT, path + ": " + what); }
[[noreturn]] void internal_error(const std::string& path, const std::string& what) { fail(SSC_ERROR_INTERNAL, path + ": " + what); }

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// The next whitespace-separated token as a number, read whole by strtod (unlike operator>>, it
// takes "nan" and "inf" as a binary file's bytes give them); false at the end or on a non-number.
bool read_number(std::istream& in, double& value) {
    std::string token;
    if (!(in >> token)) return false;
    char* end = nullptr;
    value = std::strtod(token.c_str(), &end);
    return end == token.c_str() + token.size();
}

// A unit vector along v, or zero when v has no direction: computed without overflow, so huge
// finite components still give a finite unit vector.
Eigen::Vector3d unit_or_zero(const Eigen::Vector3d& v) {
    if (!v.allFinite()) return Eigen::Vector3d::Zero();
    const double len = v.stableNorm();
    return len > 0 && std::isfinite(len) ? Eigen::Vector3d(v / len) : Eigen::Vector3d::Zero();
}

// Unit normals where usable, zero where not; empty when none is usable.
std::vector<Eigen::Vector3d> usable_normals(std::vector<Eigen::Vector3d> normals) {
    bool any = false;
    for (auto& v : normals) {
        v = unit_or_zero(v);
        any = any || v.squaredNorm() > 0;
    }
    if (!any) normals.clear();
    return normals;
}

// Normals from faces (area weighted), for files that give faces but no normals. Computed on the
// points scaled into the unit cube: finite coordinates near the largest double would otherwise make
// edge vectors and cross products overflow to Inf and the normals NaN.
std::vector<Eigen::Vector3d> face_normals(const std::vector<Eigen::Vector3d>& pts, const std::vector<uint32_t>& tris) {
    double extent = 0;
    for (const auto& p : pts) extent = std::max(extent, p.cwiseAbs().maxCoeff());
    const double scale = extent > 0 ? 1.0 / extent : 1.0;
    std::vector<Eigen::Vector3d> n(pts.size(), Eigen::Vector3d::Zero());
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
        const Eigen::Vector3d a = pts[tris[t]] * scale;
        const Eigen::Vector3d f = (pts[tris[t + 1]] * scale - a).cross(pts[tris[t + 2]] * scale - a);
        for (int i = 0; i < 3; ++i) n[tris[t + i]] += f;
    }
    // Points on no face get a zero normal (unknown: the fitter estimates it); none at all when no
    // point got one.
    return usable_normals(std::move(n));
}

// Normals given per point in a file: each usable one kept as a unit vector, the others (zero,
// non-finite: common in real scans) set to zero, meaning unknown; none when no point has one.
std::vector<Eigen::Vector3d> given_normals(std::vector<Eigen::Vector3d> normals) { return usable_normals(std::move(normals)); }

// What every point reader returns: some points, and either no normals or one normal per point, a
// finite unit vector or zero (unknown).
PointFile checked(PointFile f, const std::string& path) {
    if (f.points.empty()) bad(path, "holds no points");
    if (!f.normals.empty() && f.normals.size() != f.points.size())
        internal_error(path, "a reader returned " + std::to_string(f.normals.size()) + " normals for " + std::to_string(f.points.size()) + " points");
    for (const auto& n : f.normals)
        if (!n.allFinite() || (n.squaredNorm() != 0 && std::abs(n.squaredNorm() - 1.0) > 1e-6))
            internal_error(path, "a reader returned a normal that is neither a finite unit vector nor zero");
    return f;
}

// --- PLY -----------------------------------------------------------------------------------------

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

PlyType ply_type(const std::string& path, const std::string& t) {
    if (t == "char" || t == "int8") return PlyType::I8;
    if (t == "uchar" || t == "uint8") return PlyType::U8;
    if (t == "short" || t == "int16") return PlyType::I16;
    if (t == "ushort" || t == "uint16") return PlyType::U16;
    if (t == "int" || t == "int32") return PlyType::I32;
    if (t == "uint" || t == "uint32") return PlyType::U32;
    if (t == "float" || t == "float32") return PlyType::F32;
    if (t == "double" || t == "float64") return PlyType::F64;
    bad(path, "unknown PLY property type '" + t + "'");
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::I8: case PlyType::U8: return 1;
        case PlyType::I16: case PlyType::U16: return 2;
        case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
        case PlyType::F64: return 8;
    }
    return 0;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::F32;
    bool list = false;
    PlyType count_type = PlyType::U8;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> props;
};

// Reads values from an ascii or binary body.
class PlyCursor {
public:
    PlyCursor(const std::string& path, const std::string& data, std::size_t pos, int format)
        : path_(path), data_(data), pos_(pos), format_(format) {
        if (format_ == 0) text_.str(data.substr(pos));
    }
    double read(PlyType t) {
        if (format_ == 0) {
            // strtod, not operator>>: "nan" and "inf" read as a binary file's NaN and Inf do (the
            // readers then treat a non-finite normal as unknown, a non-finite position as an error).
            double v;
            if (!read_number(text_, v)) bad(path_, "PLY data ends early or holds a non-number");
            return v;
        }
        const std::size_t n = ply_size(t);
        if (pos_ + n > data_.size()) bad(path_, "PLY data ends early at byte " + std::to_string(pos_));
        unsigned char b[8];
        std::memcpy(b, data_.data() + pos_, n);
        pos_ += n;
        if (format_ == 2) std::reverse(b, b + n);  // big endian
        switch (t) {
            case PlyType::I8: { int8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::U8: return b[0];
            case PlyType::I16: { int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::U16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::I32: { int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::U32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::F32: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::F64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
    }
    std::size_t remaining() const { return format_ == 0 ? data_.size() : data_.size() - pos_; }
    // What is left after the last declared element, whitespace aside: a header that under-counts its
    // elements (the rest of the scan would be ignored) or two files joined.
    std::size_t trailing_bytes() {
        if (format_ != 0) {
            std::size_t n = data_.size() - pos_;
            while (n > 0 && std::isspace(static_cast<unsigned char>(data_[pos_ + n - 1]))) --n;  // a final newline
            return n;
        }
        text_ >> std::ws;
        if (text_.eof()) return 0;
        const std::streamoff at = text_.tellg();
        return at < 0 ? 1 : data_.size() - pos_ - std::size_t(at);  // ASCII: pos_ stays where the text starts
    }

private:
    const std::string& path_;
    const std::string& data_;
    std::size_t pos_;
    int format_;  // 0 ascii, 1 little endian, 2 big endian
    std::istringstream text_;
};

PointFile ply_points(const std::string& data, const std::string& path) {
    const std::size_t end = data.find("end_header");
    if (data.compare(0, 3, "ply") != 0 || end == std::string::npos) bad(path, "not a PLY file (no 'ply' magic or 'end_header')");
    std::size_t body = data.find('\n', end);
    if (body == std::string::npos) bad(path, "PLY header is not terminated by a newline");
    ++body;
    std::istringstream header(data.substr(0, end));
    std::string line;
    int format = -1;
    std::vector<PlyElement> elements;
    while (std::getline(header, line)) {
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "format") {
            std::string f;
            ls >> f;
            format = f == "ascii" ? 0 : f == "binary_little_endian" ? 1 : f == "binary_big_endian" ? 2 : -1;
            if (format < 0) bad(path, "unknown PLY format '" + f + "'");
        } else if (word == "element") {
            PlyElement e;
            if (!(ls >> e.name >> e.count)) bad(path, "malformed PLY element line '" + line + "'");
            elements.push_back(e);
        } else if (word == "property") {
            if (elements.empty()) bad(path, "PLY property before any element");
            PlyProperty p;
            std::string t;
            ls >> t;
            if (t == "list") {
                std::string ct, it;
                ls >> ct >> it >> p.name;
                p.list = true;
                p.count_type = ply_type(path, ct);
                p.type = ply_type(path, it);
            } else {
                p.type = ply_type(path, t);
                ls >> p.name;
            }
            elements.back().props.push_back(p);
        }
    }
    if (format < 0) bad(path, "PLY header has no format line");
    PlyCursor cur(path, data, body, format);
    PointFile out;
    std::vector<Eigen::Vector3d> normals;
    std::vector<uint32_t> tris;
    bool seen_vertex = false;
    for (const auto& e : elements) {
        if (e.name == "vertex") {
            if (seen_vertex) bad(path, "PLY file has more than one 'vertex' element");
            seen_vertex = true;
        }
        // An element without properties holds no data: there is nothing to read for any of its entries.
        if (e.props.empty()) continue;
        // Hostile counts: every element needs at least one byte per property, so a count larger
        // than the remaining file is an error before anything is allocated for it.
        if (e.count > cur.remaining()) bad(path, "PLY element '" + e.name + "' claims " + std::to_string(e.count) + " entries, more than the file holds");
        int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, ifaces = -1;
        for (std::size_t i = 0; i < e.props.size(); ++i) {
            const auto& n = e.props[i].name;
            if (n == "x") ix = int(i);
            if (n == "y") iy = int(i);
            if (n == "z") iz = int(i);
            if (n == "nx") inx = int(i);
            if (n == "ny") iny = int(i);
            if (n == "nz") inz = int(i);
            if (n == "vertex_indices" || n == "vertex_index") ifaces = int(i);
        }
        const bool vertex = e.name == "vertex";
        if (vertex && (ix < 0 || iy < 0 || iz < 0)) bad(path, "PLY vertex element lacks x, y or z");
        const bool has_normals = vertex && inx >= 0 && iny >= 0 && inz >= 0;
        std::vector<double> values(e.props.size());
        for (uint64_t r = 0; r < e.count; ++r) {
            std::vector<uint32_t> poly;
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const auto& p = e.props[i];
                if (!p.list) {
                    values[i] = cur.read(p.type);
                    continue;
                }
                const double n = cur.read(p.count_type);
                if (!(n >= 0 && n <= 1024)) bad(path, "PLY list of " + std::to_string(n) + " entries");
                for (int k = 0; k < int(n); ++k) {
                    const double idx = cur.read(p.type);
                    if (int(i) == ifaces) {
                        if (!(idx >= 0 && idx < double(out.points.size()))) bad(path, "PLY face index " + std::to_string(idx) + " out of range");
                        poly.push_back(uint32_t(idx));
                    }
                }
            }
            if (vertex) {
                const Eigen::Vector3d p(values[std::size_t(ix)], values[std::size_t(iy)], values[std::size_t(iz)]);
                if (!finite(p)) bad(path, "PLY vertex " + std::to_string(r) + " is not finite");
                out.points.push_back(p);
                if (has_normals) normals.emplace_back(values[std::size_t(inx)], values[std::size_t(iny)], values[std::size_t(inz)]);
            }
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) tris.insert(tris.end(), {poly[0], poly[k], poly[k + 1]});
        }
    }
    if (const std::size_t left = cur.trailing_bytes(); left > 0)
        bad(path, std::to_string(left) + " bytes follow the elements the header declares (" + std::to_string(out.points.size()) +
                      " vertices): the header under-counts them, or another file follows");
    // Normals the file does not give usably come from the faces where it has them, else from the fitter.
    out.normals = given_normals(std::move(normals));
    const bool missing = out.normals.empty() ||
                         std::any_of(out.normals.begin(), out.normals.end(), [](const Eigen::Vector3d& n) { return n.squaredNorm() == 0; });
    if (!tris.empty() && missing) {
        const auto from_faces = face_normals(out.points, tris);
        if (out.normals.empty()) out.normals = from_faces;
        else if (!from_faces.empty())
            for (std::size_t i = 0; i < out.normals.size(); ++i)
                if (out.normals[i].squaredNorm() == 0) out.normals[i] = from_faces[i];
    }
    return out;
}

// --- OBJ -----------------------------------------------------------------------------------------

PointFile obj_points(const std::string& data, const std::string& path) {
    std::istringstream in(data);
    std::string line;
    PointFile out;
    std::vector<Eigen::Vector3d> vn;
    std::vector<uint32_t> tris;
    std::size_t number = 0;
    while (std::getline(in, line)) {
        ++number;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v" || tag == "vn") {
            // Numbers as strtod reads them, as the PLY reader does: a normal of "nan" is unknown (one
            // rule for both formats: real scanners write NaN normals), a position must be finite.
            Eigen::Vector3d p;
            const bool read = read_number(ls, p.x()) && read_number(ls, p.y()) && read_number(ls, p.z());
            if (!read || (tag == "v" && !finite(p))) bad(path, "line " + std::to_string(number) + ": malformed '" + tag + "'");
            (tag == "v" ? out.points : vn).push_back(p);
        } else if (tag == "f") {
            std::vector<uint32_t> poly;
            std::string ref;
            while (ls >> ref) {
                const long idx = std::strtol(ref.c_str(), nullptr, 10);
                const long n = long(out.points.size());
                const long resolved = idx < 0 ? n + idx : idx - 1;  // OBJ indices are 1-based, negative = relative
                if (resolved < 0 || resolved >= n) bad(path, "line " + std::to_string(number) + ": face index out of range");
                poly.push_back(uint32_t(resolved));
            }
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) tris.insert(tris.end(), {poly[0], poly[k], poly[k + 1]});
        }
    }
    if (!tris.empty()) {
        out.normals = face_normals(out.points, tris);
    } else if (vn.size() == out.points.size()) {
        out.normals = given_normals(std::move(vn));
    }
    return out;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
    return true;
}

}  // namespace

PointFile parse_ply(const std::string& data, const std::string& name) { return checked(ply_points(data, name), name); }
PointFile parse_obj(const std::string& data, const std::string& name) { return checked(obj_points(data, name), name); }

PointFile read_points(const std::string& path) {
    if (!ends_with(path, ".ply") && !ends_with(path, ".obj")) bad(path, "unknown point file type (expected .ply or .obj)");
    return parse_points(slurp(path), path);
}

PointFile parse_points(const std::string& data, const std::string& name) {
    if (ends_with(name, ".ply")) return parse_ply(data, name);
    if (ends_with(name, ".obj")) return parse_obj(data, name);
    bad(name, "unknown point file type (expected .ply or .obj)");
}

std::vector<LandmarkRecord> read_lnd(const std::string& path) { return parse_lnd(slurp(path), path); }

DepthImage read_pgm_depth(const std::string& path) { return parse_pgm_depth(slurp(path), path); }

std::string normalized_landmark_name(const std::string& name) {
    std::string out;
    for (char c : name)
        if (std::isalnum(static_cast<unsigned char>(c))) out += char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::vector<LandmarkRecord> parse_lnd(const std::string& data, const std::string& path) {
    std::istringstream in(data);
    std::string line;
    bool rows = false, ended = false;
    std::size_t number = 0;
    std::vector<LandmarkRecord> out;
    std::unordered_map<std::string, std::size_t> seen;  // normalized name -> its line
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ls(line);
        std::string first;
        ls >> first;
        if (!rows) {
            if (first == "AUX") rows = true;
            continue;
        }
        if (first == "END") {
            ended = true;
            break;
        }
        if (first.empty()) continue;
        // index, status, status, a fourth number, x, y, z, name (may contain spaces).
        double index, s1, s2, fourth, x, y, z;
        std::istringstream row(line);
        if (!(row >> index >> s1 >> s2 >> fourth >> x >> y >> z))
            bad(path, "line " + std::to_string(number) + ": expected index, two status columns, a number, x, y, z and a name");
        std::string name;
        std::getline(row, name);
        const auto b = name.find_first_not_of(" \t");
        name = b == std::string::npos ? "" : name.substr(b);
        // One name twice is two measurements of one point that disagree: no rule picks one.
        if (const std::string key = normalized_landmark_name(name); !key.empty()) {
            const auto [it, first_time] = seen.emplace(key, number);
            if (!first_time)
                bad(path, "line " + std::to_string(number) + ": landmark '" + name + "' is listed twice (first on line " +
                              std::to_string(it->second) + ")");
        }
        if (s1 == -999 || s2 == -999) continue;  // not found on this subject
        LandmarkRecord r;
        if (!(index >= 1 && index < 1e6)) bad(path, "line " + std::to_string(number) + ": landmark index out of range");
        r.index = uint32_t(index);
        r.name = name;
        r.position = Eigen::Vector3d(x, y, z) / 1000.0;
        if (!finite(r.position)) bad(path, "line " + std::to_string(number) + ": coordinates are not finite");
        out.push_back(r);
    }
    if (!rows) bad(path, "no 'AUX =' line: not a CAESAR .lnd file");
    if (!ended) bad(path, "no 'END =' line: the file is truncated");
    return out;
}

DepthImage parse_pgm_depth(const std::string& data, const std::string& path) {
    std::size_t pos = 0;
    DepthImage img;
    auto comment = [&](const std::string& line) {
        std::istringstream in(line);
        std::string hash, tag, key;
        in >> hash >> tag >> key;
        if (tag != "sscape") return;
        std::vector<double> v;
        for (double x; in >> x;) v.push_back(x);
        const bool numbers_only = in.eof();
        auto all_finite = [&]() { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
        if (key == "intrinsics") {
            if (!numbers_only || v.size() != 4 || !all_finite()) bad(path, "'# sscape intrinsics' needs 4 numbers: fx fy cx cy");
            img.has_intrinsics = true;
            img.fx = v[0], img.fy = v[1], img.cx = v[2], img.cy = v[3];
        } else if (key == "camera_to_world") {
            if (!numbers_only || v.size() != 16 || !all_finite()) bad(path, "'# sscape camera_to_world' needs 16 numbers (column-major 4x4)");
            img.has_pose = true;
            for (int i = 0; i < 16; ++i) img.camera_to_world(i % 4, i / 4) = v[std::size_t(i)];
        }
    };
    auto token = [&]() {
        for (;;) {
            while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
            if (pos < data.size() && data[pos] == '#') {
                const std::size_t start = pos;
                while (pos < data.size() && data[pos] != '\n') ++pos;
                comment(data.substr(start, pos - start));
                continue;
            }
            break;
        }
        const std::size_t start = pos;
        while (pos < data.size() && !std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
        return data.substr(start, pos - start);
    };
    if (token() != "P5") bad(path, "not a binary PGM (P5) file");
    const long w = std::strtol(token().c_str(), nullptr, 10), h = std::strtol(token().c_str(), nullptr, 10);
    const long maxval = std::strtol(token().c_str(), nullptr, 10);
    if (w <= 0 || h <= 0 || w > 16384 || h > 16384) bad(path, "image size out of range");
    if (maxval <= 255 || maxval > 65535) bad(path, "expected 16-bit samples (maxval 256..65535), got maxval " + std::to_string(maxval));
    ++pos;  // the single whitespace after maxval
    const std::size_t need = std::size_t(w) * std::size_t(h) * 2;
    if (pos > data.size() || data.size() - pos < need) bad(path, "pixel data is truncated");
    img.width = uint32_t(w);
    img.height = uint32_t(h);
    img.depth.resize(std::size_t(w) * std::size_t(h));
    const auto* p = reinterpret_cast<const unsigned char*>(data.data() + pos);
    for (std::size_t i = 0; i < img.depth.size(); ++i) img.depth[i] = float((p[2 * i] << 8) | p[2 * i + 1]) / 1000.f;
    return img;
}

}  // namespace ssc::io
