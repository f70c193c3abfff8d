#include "assets.hpp"

#include "common/error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ssc::training::mh {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(SSC_ERROR_IO, "cannot open '" + path + "'");
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

json read_json(const std::string& path) {
    try {
        return json::parse(slurp(path));
    } catch (const json::exception& e) {
        fail(SSC_ERROR_IO, "'" + path + "' is not valid JSON: " + e.what());
    }
}

// Splits text into lines without copying; calls fn(begin, end) per line.
template <class F>
void for_lines(const std::string& text, F&& fn) {
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
        const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
        const char* e = nl ? nl : end;
        fn(p, e);
        p = e + 1;
    }
}

// Slider rule for min/average/max tokens.
double side_value(const std::string& prefix, double x) {
    const double mx = std::max(0.0, 2 * x - 1), mn = std::max(0.0, 1 - 2 * x);
    if (prefix == "max") return mx;
    if (prefix == "min") return mn;
    return 1 - mx - mn;  // "average"
}

const char* const kSideQuantities[] = {"muscle", "weight", "height", "cup", "firmness"};

}  // namespace

double age_years(double a) { return a < 0.5 ? 1 + 48 * a : 25 + 130 * (a - 0.5); }
double age_slider(double years) { return years < 25 ? (years - 1) / 48 : 0.5 + (years - 25) / 130; }

double macro_weight(const std::vector<std::string>& tokens, const MacroSliders& s) {
    double w = 1;
    for (const auto& t : tokens) {
        if (t == "male") w *= s.gender;
        else if (t == "female") w *= 1 - s.gender;
        else if (t == "african") w *= s.african;
        else if (t == "asian") w *= s.asian;
        else if (t == "caucasian") w *= s.caucasian;
        else if (t == "baby" || t == "child" || t == "young" || t == "old") {
            const double a = s.age;
            double young = 0, old = 0, baby = 0, child = 0;
            if (a < 0.5) {
                baby = std::max(0.0, 1 - 5.333 * a);
                young = std::max(0.0, 3.2 * (a - 0.1875));
                child = std::max(0.0, std::min(1.0, 5.333 * a) - young);
            } else {
                old = 2 * a - 1;
                young = 1 - old;
            }
            w *= t == "baby" ? baby : t == "child" ? child : t == "young" ? young : old;
        } else if (t == "idealproportions") w *= std::max(0.0, 2 * s.proportions - 1);
        else if (t == "uncommonproportions") w *= std::max(0.0, 1 - 2 * s.proportions);
        else {
            for (const char* q : kSideQuantities) {
                const std::size_t n = std::strlen(q);
                if (t.size() > n && t.compare(t.size() - n, n, q) == 0) {
                    const double x = std::string(q) == "muscle" ? s.muscle : std::string(q) == "weight" ? s.weight
                                     : std::string(q) == "height" ? s.height : std::string(q) == "cup" ? s.breast_size
                                                                                                      : s.breast_firmness;
                    w *= side_value(t.substr(0, t.size() - n), x);
                }
            }
        }
        if (w == 0) return 0;
    }
    return w;
}

BaseMesh read_base_mesh(const std::string& path) {
    const std::string text = slurp(path);
    BaseMesh m;
    bool in_body = false;
    for_lines(text, [&](const char* b, const char* e) {
        if (e - b < 2) return;
        if (b[0] == 'v' && b[1] == ' ') {
            char* p = const_cast<char*>(b + 2);
            for (int i = 0; i < 3; ++i) m.xyz.push_back(kUnitToMetres * std::strtof(p, &p));
        } else if (b[0] == 'v' && b[1] == 't') {
            char* p = const_cast<char*>(b + 3);
            for (int i = 0; i < 2; ++i) m.uvs.push_back(std::strtof(p, &p));
        } else if (b[0] == 'g' && b[1] == ' ') {
            in_body = std::string(b + 2, e) == "body" || std::string(b + 2, e) == "body\r";
        } else if (b[0] == 'f' && b[1] == ' ' && in_body) {
            std::vector<uint32_t> vs, ts;
            const char* p = b + 2;
            while (p < e) {
                while (p < e && *p == ' ') ++p;
                if (p >= e || *p == '\r') break;
                char* q = nullptr;
                vs.push_back(uint32_t(std::strtoul(p, &q, 10) - 1));
                uint32_t t = 0;
                if (*q == '/') t = uint32_t(std::strtoul(q + 1, &q, 10) - 1);
                ts.push_back(t);
                while (q < e && *q != ' ') ++q;
                p = q;
            }
            if (vs.size() != 4) fail(SSC_ERROR_IO, "'" + path + "': a body face is not a quad");
            m.body_quads.insert(m.body_quads.end(), vs.begin(), vs.end());
            m.body_quad_uvs.insert(m.body_quad_uvs.end(), ts.begin(), ts.end());
        }
    });
    m.vertex_count = uint32_t(m.xyz.size() / 3);
    if (m.vertex_count < kBodyVertices || m.body_quads.empty())
        fail(SSC_ERROR_IO, "'" + path + "' does not hold the hm08 base mesh");
    for (uint32_t v : m.body_quads)
        if (v >= kBodyVertices) fail(SSC_ERROR_IO, "'" + path + "': a body face uses a helper vertex");
    return m;
}

Target read_target(const std::string& path) {
    const std::string text = slurp(path);
    Target t;
    for_lines(text, [&](const char* b, const char* e) {
        while (b < e && (*b == ' ' || *b == '\t')) ++b;
        if (b >= e || *b == '#' || *b == '\r') return;
        char* p = nullptr;
        const unsigned long v = std::strtoul(b, &p, 10);
        if (p == b) return;
        t.vertices.push_back(uint32_t(v));
        for (int i = 0; i < 3; ++i) t.deltas.push_back(kUnitToMetres * std::strtof(p, &p));
    });
    return t;
}

Rig read_rig(const std::string& path) {
    const json j = read_json(path);
    Rig r;
    for (const auto& [name, b] : j.at("bones").items()) {
        Bone bone;
        bone.name = name;
        bone.parent = b.at("parent").is_null() ? "" : b.at("parent").get<std::string>();
        bone.head = b.at("head").get<std::string>();
        bone.tail = b.at("tail").get<std::string>();
        if (b.contains("roll") && b.at("roll").is_number()) bone.roll = b.at("roll").get<double>();
        if (b.contains("reference") && b.at("reference").is_array()) bone.reference = b.at("reference").get<std::vector<std::string>>();
        if (b.contains("weights_reference") && b.at("weights_reference").is_array())
            bone.weights_reference = b.at("weights_reference").get<std::vector<std::string>>();
        r.bones.push_back(std::move(bone));
    }
    for (const auto& [name, vs] : j.at("joints").items()) r.joints[name] = vs.get<std::vector<uint32_t>>();
    // Parents before children (the file is alphabetical).
    std::vector<Bone> ordered;
    std::vector<bool> placed(r.bones.size(), false);
    while (ordered.size() < r.bones.size()) {
        const std::size_t before = ordered.size();
        for (std::size_t i = 0; i < r.bones.size(); ++i) {
            if (placed[i]) continue;
            const bool ready = r.bones[i].parent.empty() ||
                               std::any_of(ordered.begin(), ordered.end(), [&](const Bone& o) { return o.name == r.bones[i].parent; });
            if (ready) {
                ordered.push_back(r.bones[i]);
                placed[i] = true;
            }
        }
        if (ordered.size() == before) fail(SSC_ERROR_IO, "'" + path + "': bone parents form a cycle or name unknown bones");
    }
    r.bones = std::move(ordered);
    return r;
}

RigWeights read_rig_weights(const std::string& path) {
    const json j = read_json(path);
    RigWeights w;
    for (const auto& [bone, list] : j.at("weights").items())
        for (const auto& pair : list) w[bone].emplace_back(pair.at(0).get<uint32_t>(), pair.at(1).get<float>());
    return w;
}

void add_modifier_groups(Assets& a, const std::string& file, const std::vector<std::string>& groups) {
    const fs::path data = fs::path(a.root) / "makehuman" / "makehuman" / "data";
    const fs::path targets = data / "targets";
    const json j = read_json((data / "modifiers" / file).string());
    for (const auto& group : j) {
        const std::string g = group.at("group").get<std::string>();
        if (std::find(groups.begin(), groups.end(), g) == groups.end()) continue;
        for (const auto& mod : group.at("modifiers")) {
            if (!mod.contains("target")) continue;  // macro variables are handled by load_assets
            const std::string t = mod.at("target").get<std::string>();
            if (t == "stomach-pregnant" || t == "bulge" || t.rfind("nipple", 0) == 0) continue;
            Modifier m;
            auto load = [&](const std::string& name) {
                const fs::path p = targets / g / (name + ".target");
                if (!fs::exists(p)) fail(SSC_ERROR_IO, "missing target " + p.string());
                a.modifier_targets.push_back(read_target(p.string()));
                return int(a.modifier_targets.size()) - 1;
            };
            if (mod.contains("min") && mod.contains("max")) {
                m.name = g + "/" + t + "-" + mod.at("min").get<std::string>() + "|" + mod.at("max").get<std::string>();
                m.decr = load(t + "-" + mod.at("min").get<std::string>());
                m.incr = load(t + "-" + mod.at("max").get<std::string>());
            } else {
                m.name = g + "/" + t;
                m.incr = load(t);
            }
            a.modifiers.push_back(std::move(m));
        }
    }
}

Assets load_assets(const std::string& root) {
    Assets a;
    a.root = root;
    const fs::path data = fs::path(root) / "makehuman" / "makehuman" / "data";
    const fs::path targets = data / "targets";
    if (!fs::is_directory(targets)) fail(SSC_ERROR_IO, "'" + root + "' does not hold the MakeHuman assets (no " + targets.string() + ")");
    a.base = read_base_mesh((data / "3dobjs" / "base.obj").string());

    // Macro targets: macrodetails (with height/ and proportions/) and the breast size/firmness set.
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(targets / "macrodetails"))
        if (e.path().extension() == ".target") files.push_back(e.path());
    for (const auto& e : fs::directory_iterator(targets / "breast"))
        if (e.path().extension() == ".target" && e.path().filename().string().rfind("breast-", 0) != 0 &&
            e.path().filename().string().rfind("nipple-", 0) != 0)
            files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        MacroTarget m;
        m.name = fs::relative(f, targets).string();
        std::stringstream ss(f.stem().string());
        std::string tok;
        while (std::getline(ss, tok, '-')) m.tokens.push_back(tok);
        m.target = read_target(f.string());
        a.macro_targets.push_back(std::move(m));
    }
    // Known defect: two old-age height targets are nearly empty; their averageweight sibling stands in.
    for (auto& m : a.macro_targets) {
        if (m.name.find("height/") == std::string::npos || m.target.size() > 100) continue;
        std::string sibling = m.name;
        const auto at = sibling.find("maxweight");
        if (at == std::string::npos) continue;
        sibling.replace(at, 9, "averageweight");
        for (const auto& s : a.macro_targets)
            if (s.name == sibling) m.target = s.target;
    }

    // Body-shape modifiers. Left out on purpose: pregnancy, genital bulge and nipples (not
    // population variation), and the face/hand/foot detail groups.
    add_modifier_groups(a, "measurement_modifiers.json", {"measure"});
    add_modifier_groups(a, "modeling_modifiers.json", {"torso", "hip", "stomach", "buttocks", "pelvis", "breast"});
    add_modifier_groups(a, "bodyshapes_modifiers.json", {"bodyshapes"});

    a.default_rig = read_rig((data / "rigs" / "default.mhskel").string());
    a.default_weights = read_rig_weights((data / "rigs" / "default_weights.mhw").string());
    a.game_rig = read_rig((fs::path(root) / "makehuman-assets" / "base" / "rigs" / "game_engine.mhskel").string());
    std::ifstream manifest((fs::path(root) / "MANIFEST.sha256").string());
    std::string line;
    while (std::getline(manifest, line) && line.rfind("#", 0) == 0) a.manifest += line + "\n";
    return a;
}

void generate_body(const Assets& a, const MacroSliders& s, const std::vector<double>& mods, std::vector<float>& xyz) {
    xyz = a.base.xyz;
    auto add = [&](const Target& t, double w) {
        const float fw = float(w);
        for (std::size_t i = 0; i < t.vertices.size(); ++i) {
            float* p = &xyz[3 * std::size_t(t.vertices[i])];
            p[0] += fw * t.deltas[3 * i];
            p[1] += fw * t.deltas[3 * i + 1];
            p[2] += fw * t.deltas[3 * i + 2];
        }
    };
    for (const auto& m : a.macro_targets) {
        const double w = macro_weight(m.tokens, s);
        if (w > 1e-9) add(m.target, w);
    }
    for (std::size_t i = 0; i < mods.size() && i < a.modifiers.size(); ++i) {
        const Modifier& m = a.modifiers[i];
        const double v = mods[i];
        if (m.decr >= 0) {
            if (v < 0) add(a.modifier_targets[m.decr], -v);
            if (v > 0) add(a.modifier_targets[m.incr], v);
        } else if (v > 0) {
            add(a.modifier_targets[m.incr], v);
        }
    }
}

}  // namespace ssc::training::mh
