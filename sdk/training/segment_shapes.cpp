#include "segment_shapes.hpp"

#include "common/error.hpp"
#include "common/rigid.hpp"
#include "sscape_format/model_io.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace ssc::training {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Edges {
    std::vector<uint32_t> offsets, to;
    std::vector<double> length;
};

Edges mesh_edges(const format::ModelData& m) {
    const uint32_t V = m.vertex_count();
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    const auto& t = m.mesh.triangles;
    for (std::size_t i = 0; i + 2 < t.size(); i += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = t[i + e], b = t[i + (e + 1) % 3];
            pairs.emplace_back(a, b);
            pairs.emplace_back(b, a);
        }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    Edges g;
    g.offsets.assign(V + 1, 0);
    for (const auto& p : pairs) ++g.offsets[p.first + 1];
    for (uint32_t v = 0; v < V; ++v) g.offsets[v + 1] += g.offsets[v];
    for (const auto& p : pairs) {
        g.to.push_back(p.second);
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
            const double d = double(m.shape.mean[3 * p.first + a]) - double(m.shape.mean[3 * p.second + a]);
            d2 += d * d;
        }
        g.length.push_back(std::sqrt(d2));
    }
    return g;
}

// Geodesic distance (over the edges) from the vertices where `source` is true, up to `limit`.
std::vector<double> distance_from(const Edges& g, const std::vector<char>& source, double limit) {
    std::vector<double> d(source.size(), kInf);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (uint32_t v = 0; v < source.size(); ++v)
        if (source[v]) d[v] = 0, queue.emplace(0.0, v);
    while (!queue.empty()) {
        const auto [dv, v] = queue.top();
        queue.pop();
        if (dv > d[v]) continue;
        for (uint32_t e = g.offsets[v]; e < g.offsets[v + 1]; ++e) {
            const double dn = dv + g.length[e];
            if (dn < d[g.to[e]] && dn <= limit) d[g.to[e]] = dn, queue.emplace(dn, g.to[e]);
        }
    }
    return d;
}

double smoothstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

}  // namespace

std::vector<SegmentLayout> segment_layout(const format::ModelData& m, double band) {
    SSC_REQUIRE_ARG_S(std::isfinite(band) && band >= 0 && band <= 0.5, "segments: the blend band is " << band << " m; it must lie in [0, 0.5]");
    const uint32_t V = m.vertex_count();
    const std::vector<std::string> names = {"head", "arm_l", "arm_r", "torso", "leg_l", "leg_r"};
    // Vertex set -> segment: arms and legs split by side.
    struct Part {
        const char* set;
        int centre, left, right;
    };
    const Part parts[] = {{"head", 0, 0, 0}, {"arms", -1, 1, 2}, {"hands", -1, 1, 2}, {"torso", 3, 3, 3}, {"legs", -1, 4, 5}, {"feet", -1, 4, 5}};
    std::vector<int> label(V, -1);
    for (const Part& p : parts) {
        const auto it = std::find_if(m.vertex_sets.begin(), m.vertex_sets.end(), [&](const format::VertexSet& s) { return s.name == p.set; });
        SSC_REQUIRE_ARG_S(it != m.vertex_sets.end(), "segments: the model has no vertex set '" << p.set
                                                         << "' (segments need head, torso, arms, hands, legs and feet)");
        for (uint32_t v : it->vertices)
            label[v] = p.centre >= 0 ? p.centre : (m.shape.mean[3 * v] >= 0 ? p.left : p.right);
    }
    for (uint32_t v = 0; v < V; ++v)
        SSC_REQUIRE_ARG_S(label[v] >= 0, "segments: vertex " << v << " is in none of the body-part vertex sets");

    // Each segment's raw weight falls from 1 at `band` inside its border to 0 at `band` outside
    // (0.5 on the border), then the weights are normalised to sum to 1 at every vertex.
    const Edges g = mesh_edges(m);
    std::vector<std::vector<double>> raw(names.size());
    for (std::size_t s = 0; s < names.size(); ++s) {
        std::vector<char> inside(V), outside(V);
        for (uint32_t v = 0; v < V; ++v) inside[v] = label[v] == int(s), outside[v] = !inside[v];
        const std::vector<double> to_inside = distance_from(g, inside, band), to_outside = distance_from(g, outside, band);
        raw[s].assign(V, 0.0);
        for (uint32_t v = 0; v < V; ++v) {
            if (band == 0) {
                raw[s][v] = inside[v];
                continue;
            }
            const double signed_distance = inside[v] ? -std::min(to_outside[v], band) : std::min(to_inside[v], band);
            raw[s][v] = smoothstep((band - signed_distance) / (2 * band));
        }
    }
    std::vector<SegmentLayout> out(names.size());
    for (std::size_t s = 0; s < names.size(); ++s) out[s].name = names[s];
    for (uint32_t v = 0; v < V; ++v) {
        double sum = 0;
        for (const auto& r : raw) sum += r[v];  // >= 0.5: the vertex's own segment
        for (std::size_t s = 0; s < names.size(); ++s) {
            const float w = float(raw[s][v] / sum);
            if (w < 1e-4f) continue;  // below any visible effect; the sum stays <= 1
            out[s].vertices.push_back(v);
            out[s].weights.push_back(std::min(w, 1.f));
        }
    }
    return out;
}

namespace {

// Where a segment overlaps the segment it hangs from (for the torso, the root: where the legs hang
// from it), weighted by the product of the two blend weights, which peaks on the border.
struct Attached {
    uint32_t vertex;
    Eigen::Index at;  // position in the segment's vertices
    double weight;
};

std::vector<Attached> attachment(const std::vector<SegmentLayout>& layout, std::size_t s, std::size_t torso) {
    std::vector<std::size_t> others;
    if (s != torso) others.push_back(torso);
    else
        for (std::size_t o = 0; o < layout.size(); ++o)
            if (layout[o].name.rfind("leg", 0) == 0) others.push_back(o);
    const SegmentLayout& me = layout[s];
    std::vector<Attached> out;
    for (std::size_t o : others) {
        const SegmentLayout& other = layout[o];
        for (std::size_t i = 0, j = 0; i < me.vertices.size() && j < other.vertices.size();) {
            if (me.vertices[i] < other.vertices[j]) ++i;
            else if (me.vertices[i] > other.vertices[j]) ++j;
            else out.push_back({me.vertices[i], Eigen::Index(i), double(me.weights[i]) * double(other.weights[j])}), ++i, ++j;
        }
    }
    return out;
}

// A segment's rigid frame: the rotation that best takes its core (the vertices that are mostly
// its own) onto the mean's, and the translation that keeps its attachment where the mean's is.
// The segment's shape is then its vertices in that frame, as displacements from the mean: how a
// head or an arm differs, not where the body holds it (posture that normalization left, stature).
struct SegmentFrame {
    std::vector<Eigen::Index> core;  // positions in the segment's vertices
    std::vector<Attached> attach;
    Eigen::Matrix3Xd mean;           // the mean's vertices
};

// positions: the segment's vertices of one body (3 x n); returns 3n displacements, x y z per vertex.
Eigen::RowVectorXf segment_shape(const SegmentFrame& f, const Eigen::Matrix3Xd& positions) {
    Eigen::Matrix3Xd src(3, Eigen::Index(f.core.size())), dst(3, Eigen::Index(f.core.size()));
    for (std::size_t c = 0; c < f.core.size(); ++c) src.col(Eigen::Index(c)) = positions.col(f.core[c]), dst.col(Eigen::Index(c)) = f.mean.col(f.core[c]);
    const Eigen::Matrix3d R = align_points(src, dst, false).R;
    const Eigen::Matrix3Xd d = R * positions - f.mean;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double weight = 0;
    for (const Attached& a : f.attach) t += a.weight * d.col(a.at), weight += a.weight;
    t /= weight;
    Eigen::RowVectorXf out(3 * positions.cols());
    for (Eigen::Index i = 0; i < positions.cols(); ++i) out.segment(3 * i, 3) = (d.col(i) - t).transpose().cast<float>();
    return out;
}

}  // namespace

std::vector<format::ShapeSegment> learn_segments(const format::ModelData& m, const SampleMatrix& X, Eigen::Index rows, const Pca& whole,
                                                 const SegmentSpec& spec, std::vector<SegmentCompactness>* compactness) {
    SSC_REQUIRE_ARG_S(spec.components >= 1 && Eigen::Index(spec.components) < rows,
                      "segments: " << spec.components << " components per segment need more than that many bodies (" << rows << ")");
    SSC_REQUIRE_ARG_S(spec.band >= 0.005, "segments: the blend band is " << spec.band << " m; segments need at least 5 mm to blend");
    const uint32_t V = m.vertex_count();
    const std::vector<SegmentLayout> layout = segment_layout(m, spec.band);
    const std::size_t torso = std::size_t(std::find_if(layout.begin(), layout.end(), [](const SegmentLayout& l) { return l.name == "torso"; }) - layout.begin());
    // The whole body's coefficients of every body, for its share of each segment's variance.
    const Eigen::MatrixXf coefficients = X.topRows(rows) * whole.basis;  // N x K
    std::vector<Eigen::MatrixXf> bases(layout.size());                  // per segment: its PCA over its own vertices (3n x K)
    std::vector<Eigen::VectorXd> stddevs(layout.size());
    if (compactness) compactness->clear();
    for (std::size_t s = 0; s < layout.size(); ++s) {
        const SegmentLayout& l = layout[s];
        const auto n = Eigen::Index(l.vertices.size());
        SegmentFrame frame;
        frame.attach = attachment(layout, s, torso);
        SSC_REQUIRE_ARG_S(!frame.attach.empty(), "segments: " << l.name << " does not touch the segment it hangs from");
        frame.mean.resize(3, n);
        for (Eigen::Index i = 0; i < n; ++i) {
            frame.mean.col(i) = whole.mean.segment(3 * Eigen::Index(l.vertices[std::size_t(i)]), 3).cast<double>();
            if (l.weights[std::size_t(i)] >= 0.5f) frame.core.push_back(i);
        }
        SSC_REQUIRE_ARG_S(frame.core.size() >= 3, "segments: " << l.name << " has fewer than 3 vertices of its own");
        // positions(body, k): the segment's vertices of a body, or of its reconstruction by the whole body's first k components.
        auto positions = [&](Eigen::Index b, Eigen::Index k) {
            Eigen::Matrix3Xd p(3, n);
            for (Eigen::Index i = 0; i < n; ++i) {
                const Eigen::Index c = 3 * Eigen::Index(l.vertices[std::size_t(i)]);
                const Eigen::Vector3f d = k < 0 ? Eigen::Vector3f(X.block(b, c, 1, 3).transpose())
                                                : Eigen::Vector3f(whole.basis.block(c, 0, 3, k) * coefficients.row(b).head(k).transpose());
                p.col(i) = frame.mean.col(i) + d.cast<double>();
            }
            return p;
        };
        SampleMatrix Xs(rows, 3 * n);
        for (Eigen::Index b = 0; b < rows; ++b) Xs.row(b) = segment_shape(frame, positions(b, -1));
        if (compactness) {
            SegmentCompactness c;
            c.name = l.name;
            c.vertices = uint32_t(n);
            const double total = double(Xs.cast<double>().squaredNorm());
            c.variance = total / double(rows - 1);
            // The whole body's first k components, their reconstruction seen the same way.
            for (Eigen::Index k = 1; k <= whole.basis.cols() && k <= Eigen::Index(spec.components); ++k) {
                double residual = 0;
                for (Eigen::Index b = 0; b < rows; ++b) residual += double((Xs.row(b) - segment_shape(frame, positions(b, k))).cast<double>().squaredNorm());
                c.whole_body.push_back(total > 0 ? 1 - residual / total : 0);
            }
            compactness->push_back(std::move(c));
        }
        const Pca p = pca(Xs, rows, spec.components, spec.seed);
        bases[s] = p.basis;
        stddevs[s] = p.stddev;
        if (compactness) {
            double kept = 0;
            for (Eigen::Index k = 0; k < p.stddev.size(); ++k) {
                kept += p.stddev(k) * p.stddev(k);
                compactness->back().own.push_back(p.total_variance > 0 ? kept / p.total_variance : 0);
            }
        }
    }

    // Each component's whole effect on the body: its shape blended by the segment's weight; the
    // torso's also moves each limb and the head as its attachment moves.
    std::vector<format::ShapeSegment> out;
    for (std::size_t s = 0; s < layout.size(); ++s) {
        const SegmentLayout& l = layout[s];
        const auto K = uint32_t(bases[s].cols());
        format::ShapeSegment sg;
        sg.name = l.name;
        sg.stddev.resize(K);
        for (uint32_t k = 0; k < K; ++k) sg.stddev[k] = float(stddevs[s](k));
        if (s == torso) {
            sg.vertices.resize(V);
            for (uint32_t v = 0; v < V; ++v) sg.vertices[v] = v;
            sg.weights.assign(V, 0.f);
            for (std::size_t i = 0; i < l.vertices.size(); ++i) sg.weights[l.vertices[i]] = l.weights[i];
        } else {
            sg.vertices = l.vertices;
            sg.weights = l.weights;
        }
        const std::size_t n = sg.vertices.size();
        std::vector<float> scaled(std::size_t(K) * 3 * n, 0.f);  // planar, metres per standard deviation
        auto add = [&](uint32_t k, std::size_t i, const Eigen::Vector3d& d) {
            for (int a = 0; a < 3; ++a) scaled[(std::size_t(k) * 3 + std::size_t(a)) * n + i] += float(d[a]);
        };
        for (uint32_t k = 0; k < K; ++k) {
            const double sd = stddevs[s](k);
            // Its own vertices, blended (for the torso, listed vertex v is vertex v).
            for (std::size_t i = 0; i < l.vertices.size(); ++i)
                add(k, s == torso ? l.vertices[i] : i, sd * double(l.weights[i]) * bases[s].block(3 * Eigen::Index(i), k, 3, 1).cast<double>());
            if (s != torso) continue;
            for (std::size_t c = 0; c < layout.size(); ++c) {
                if (c == torso) continue;
                // Where child c attaches, found in the torso's own vertices.
                Eigen::Vector3d t = Eigen::Vector3d::Zero();
                double weight = 0;
                for (const Attached& a : attachment(layout, c, torso)) {
                    const auto at = Eigen::Index(std::lower_bound(l.vertices.begin(), l.vertices.end(), a.vertex) - l.vertices.begin());
                    t += a.weight * bases[s].block(3 * at, k, 3, 1).cast<double>(), weight += a.weight;
                }
                t *= sd / weight;
                for (std::size_t i = 0; i < layout[c].vertices.size(); ++i) add(k, layout[c].vertices[i], double(layout[c].weights[i]) * t);
            }
        }
        sg.basis = format::quantize_basis(scaled.data(), uint32_t(n), K, spec.tolerance);
        out.push_back(std::move(sg));
    }
    return out;
}

}  // namespace ssc::training
