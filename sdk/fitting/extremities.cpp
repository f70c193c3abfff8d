#include "fitting/extremities.hpp"

#include "fitting/nearest.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>

namespace ssc::fitting {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Neighbours each thinned scan point is joined to, and how far they may be (in spacings): enough
// to cross the gaps between a scanner's lines, too short to jump between limbs a hand apart.
constexpr std::size_t kNeighbours = 8;
// Neighbours whose normals' dot product is below this face each other: not joined.
constexpr double kFacing = 0.0;
// Pieces of the scan graph joined to the rest per round (scan_graph()).
constexpr std::size_t kMaxBridged = 16;
// A tip left out of a labelling costs this (as a mean squared relative mismatch): a hand resting
// on the body is no extremity, but a labelling that drops a tip it could match is worse.
constexpr double kMissingTip = 0.03;
// Scan geodesics over the model's that a labelling may imply: children to tall adults.
constexpr double kMinScale = 0.55, kMaxScale = 1.4;
// Right labellings of the pose library's booth scans need scales of 0.9 to 1.1; below kUsualScale
// a labelling pays kScalePenalty per kScaleSpread squared.
constexpr double kUsualScale = 0.85, kScaleSpread = 0.15, kScalePenalty = 0.02;
// A model tip lies at least this share of its part's farthest distance in space from the trunk.
constexpr double kTipReach = 0.9;

using Edges = std::vector<std::vector<std::pair<uint32_t, double>>>;

SurfaceGraph from_edges(std::vector<Vector3d> nodes, const Edges& edges) {
    SurfaceGraph g;
    g.nodes = std::move(nodes);
    g.offsets.assign(1, 0);
    for (const auto& list : edges) {
        for (const auto& [to, length] : list) g.targets.push_back(to), g.lengths.push_back(length);
        g.offsets.push_back(uint32_t(g.targets.size()));
    }
    return g;
}

// Connected pieces of a graph: each node's piece index, pieces numbered from 0.
std::vector<uint32_t> pieces(const Edges& edges, uint32_t& count) {
    std::vector<uint32_t> piece(edges.size(), ~0u);
    count = 0;
    std::vector<uint32_t> stack;
    for (uint32_t s = 0; s < edges.size(); ++s) {
        if (piece[s] != ~0u) continue;
        piece[s] = count;
        stack.assign(1, s);
        while (!stack.empty()) {
            const uint32_t n = stack.back();
            stack.pop_back();
            for (const auto& [to, length] : edges[n])
                if (piece[to] == ~0u) piece[to] = count, stack.push_back(to);
        }
        ++count;
    }
    return piece;
}

}  // namespace

SurfaceGraph scan_graph(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, double spacing) {
    // One node per occupied cube: the mean of its points.
    struct Cell {
        Vector3d sum = Vector3d::Zero(), normal = Vector3d::Zero();
        uint32_t count = 0;
    };
    std::unordered_map<uint64_t, uint32_t> cell_of;
    std::vector<Cell> cells;
    const bool with_normals = normals.size() == points.size();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vector3d& p = points[i];
        if (!p.allFinite()) continue;
        const Eigen::Vector3d c = (p / spacing).array().floor();
        // 21 bits per axis: scans within kMaxCoordinate (observations.hpp) at centimetre cubes fit.
        const auto key = [](double v) { return uint64_t(int64_t(v) & 0x1FFFFF); };
        const uint64_t k = key(c.x()) | key(c.y()) << 21 | key(c.z()) << 42;
        const auto [it, inserted] = cell_of.try_emplace(k, uint32_t(cells.size()));
        if (inserted) cells.emplace_back();
        cells[it->second].sum += p, ++cells[it->second].count;
        if (with_normals && normals[i].allFinite()) cells[it->second].normal += normals[i];
    }
    std::vector<Vector3d> nodes(cells.size());
    std::vector<Vector3d> node_normals(cells.size(), Vector3d::Zero());
    for (std::size_t i = 0; i < cells.size(); ++i) {
        nodes[i] = cells[i].sum / double(cells[i].count);
        // A cube holding both sides of a thin part (a hand) has no clear normal: it joins either.
        if (cells[i].normal.norm() > 0.5 * double(cells[i].count)) node_normals[i] = cells[i].normal.normalized();
    }
    Edges edges(nodes.size());
    if (nodes.empty()) return from_edges(std::move(nodes), edges);
    const PointIndex index(nodes);
    const double reach2 = kReach * kReach * spacing * spacing;
    std::array<uint32_t, kNeighbours + 1> near{};
    std::array<double, kNeighbours + 1> d2{};
    for (uint32_t i = 0; i < nodes.size(); ++i) {
        const std::size_t found = index.nearest_k(nodes[i], kNeighbours + 1, near.data(), d2.data());
        for (std::size_t k = 0; k < found; ++k)
            if (near[k] != i && d2[k] <= reach2 && node_normals[i].dot(node_normals[near[k]]) >= kFacing) {
                const double length = std::sqrt(d2[k]);
                edges[i].emplace_back(near[k], length), edges[near[k]].emplace_back(i, length);
            }
    }
    // Pieces cut off by holes (a hand beyond a gap at the wrist): each joined to the nearest node
    // of another piece, the kMaxBridged largest a round, until one piece holds every large one (a
    // person's scan has a few; clutter may have thousands, and each join costs a k-d tree).
    for (int round = 0; round < 8; ++round) {
        uint32_t count = 0;
        const std::vector<uint32_t> piece = pieces(edges, count);
        if (count <= 1) break;
        std::vector<std::size_t> size(count, 0);
        for (uint32_t p : piece) ++size[p];
        std::vector<uint32_t> order(count);
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return size[a] > size[b]; });
        bool joined = false;
        for (std::size_t o = 1; o < order.size() && o <= kMaxBridged; ++o) {
            const uint32_t p = order[o];
            if (size[p] < kMinPiece) break;
            // The piece's closest node pair to the rest: a k-d tree over the other pieces' nodes.
            std::vector<Vector3d> others;
            std::vector<uint32_t> other_ids;
            for (uint32_t n = 0; n < nodes.size(); ++n)
                if (piece[n] != p && size[piece[n]] >= kMinPiece) others.push_back(nodes[n]), other_ids.push_back(n);
            if (others.empty()) continue;
            const PointIndex rest(others);
            double best = kInfinity;
            uint32_t from = 0, to = 0;
            for (uint32_t n = 0; n < nodes.size(); ++n) {
                if (piece[n] != p) continue;
                double d = 0;
                const uint32_t other = rest.nearest(nodes[n], &d);
                if (d < best) best = d, from = n, to = other_ids[other];
            }
            const double length = std::sqrt(best);
            edges[from].emplace_back(to, length), edges[to].emplace_back(from, length);
            joined = true;
        }
        if (!joined) break;
    }
    return from_edges(std::move(nodes), edges);
}

SurfaceGraph mesh_graph(const std::vector<Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count) {
    Edges edges(vertices.size());
    for (std::size_t t = 0; t < triangle_count; ++t)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = triangles[3 * t + std::size_t(e)], b = triangles[3 * t + std::size_t((e + 1) % 3)];
            if (a >= vertices.size() || b >= vertices.size()) continue;
            const double length = (vertices[a] - vertices[b]).norm();
            edges[a].emplace_back(b, length), edges[b].emplace_back(a, length);
        }
    return from_edges(vertices, edges);
}

std::vector<double> geodesic_from(const SurfaceGraph& g, const std::vector<uint32_t>& sources, std::vector<uint32_t>* previous) {
    std::vector<double> d(g.nodes.size(), kInfinity);
    if (previous) {
        previous->resize(g.nodes.size());
        std::iota(previous->begin(), previous->end(), 0u);
    }
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (uint32_t s : sources)
        if (s < d.size()) d[s] = 0, queue.emplace(0.0, s);
    while (!queue.empty()) {
        const auto [dist, n] = queue.top();
        queue.pop();
        if (dist > d[n]) continue;
        for (uint32_t e = g.offsets[n]; e < g.offsets[n + 1]; ++e) {
            const double next = dist + g.lengths[e];
            if (next < d[g.targets[e]]) {
                d[g.targets[e]] = next, queue.emplace(next, g.targets[e]);
                if (previous) (*previous)[g.targets[e]] = n;
            }
        }
    }
    return d;
}

ScanExtremities scan_extremities(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, std::size_t count,
                                 double spacing) {
    ScanExtremities ex;
    const SurfaceGraph g = scan_graph(points, normals, spacing);
    if (g.nodes.empty() || count == 0) return ex;
    // The centre: the node nearest the nodes' mean.
    Vector3d mean = Vector3d::Zero();
    for (const Vector3d& n : g.nodes) mean += n;
    mean /= double(g.nodes.size());
    // Start from a node of the largest piece: the nodes nearest the mean, until one reaches half
    // the nodes.
    std::vector<uint32_t> order(g.nodes.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return (g.nodes[a] - mean).squaredNorm() < (g.nodes[b] - mean).squaredNorm(); });
    uint32_t centre = order.front();
    for (std::size_t i = 0; i < order.size() && i < 64; ++i) {
        const std::vector<double> d = geodesic_from(g, {order[i]});
        if (2 * std::size_t(std::count_if(d.begin(), d.end(), [](double v) { return std::isfinite(v); })) >= g.nodes.size()) {
            centre = order[i];
            break;
        }
    }
    std::vector<uint32_t> towards_centre;
    std::vector<double> nearest_pick = geodesic_from(g, {centre}, &towards_centre);
    std::vector<uint32_t> picks;
    std::vector<std::vector<double>> from_pick;
    for (std::size_t k = 0; k < count; ++k) {
        uint32_t best = ~0u;
        double far = 0;
        for (uint32_t n = 0; n < g.nodes.size(); ++n)
            if (std::isfinite(nearest_pick[n]) && nearest_pick[n] > far) far = nearest_pick[n], best = n;
        if (best == ~0u) break;
        picks.push_back(best);
        ex.points.push_back(g.nodes[best]);
        auto& path = ex.paths.emplace_back();
        for (uint32_t n = best, steps = 0; steps < g.nodes.size(); n = towards_centre[n], ++steps) {
            const double along = path.empty() ? 0.0 : path.back().first + (g.nodes[n] - path.back().second).norm();
            path.emplace_back(along, g.nodes[n]);
            if (along > kPathLength || towards_centre[n] == n) break;
        }
        from_pick.push_back(geodesic_from(g, {best}));
        // The first pick's own distances replace the centre's: the next is the farthest from it.
        if (k == 0) nearest_pick = from_pick.back();
        else
            for (uint32_t n = 0; n < g.nodes.size(); ++n) nearest_pick[n] = std::min(nearest_pick[n], from_pick.back()[n]);
    }
    ex.geodesic.resize(Eigen::Index(picks.size()), Eigen::Index(picks.size()));
    for (std::size_t a = 0; a < picks.size(); ++a)
        for (std::size_t b = 0; b < picks.size(); ++b) ex.geodesic(Eigen::Index(a), Eigen::Index(b)) = from_pick[a][picks[b]];
    return ex;
}

Vector3d ScanExtremities::back_along(std::size_t i, double distance) const {
    const auto& path = paths[i];
    for (std::size_t k = 1; k < path.size(); ++k)
        if (path[k].first >= distance) {
            const double a = (distance - path[k - 1].first) / std::max(1e-12, path[k].first - path[k - 1].first);
            return (1 - a) * path[k - 1].second + a * path[k].second;
        }
    return path.back().second;
}

std::vector<uint8_t> tip_parts(const LinearModel& lin) {
    using anatomy::BodyPart;
    using anatomy::Side;
    std::vector<uint8_t> parts(lin.V, kNoTip);
    for (uint32_t v = 0; v < lin.V; ++v) {
        const uint32_t j = dominant_joint(lin.model.data(), v);
        if (j >= lin.roles.size()) continue;
        const anatomy::JointRole& role = lin.roles[j];
        const int side = role.side == Side::Left ? 0 : role.side == Side::Right ? 1 : -1;
        if (role.part == BodyPart::Head) parts[v] = 0;
        else if ((role.part == BodyPart::Arm || role.part == BodyPart::Hand) && side >= 0) parts[v] = uint8_t(1 + side);
        else if ((role.part == BodyPart::Leg || role.part == BodyPart::Foot) && side >= 0) parts[v] = uint8_t(3 + side);
    }
    return parts;
}

ModelTips model_tips(const std::vector<Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count,
                     const std::vector<uint8_t>& parts) {
    ModelTips tips;
    if (parts.size() != vertices.size()) return tips;
    const SurfaceGraph g = mesh_graph(vertices, triangles, triangle_count);
    // The trunk's centre: its vertex nearest the trunk's mean.
    Vector3d mean = Vector3d::Zero();
    std::size_t trunk = 0;
    for (std::size_t v = 0; v < vertices.size(); ++v)
        if (parts[v] == kNoTip) mean += vertices[v], ++trunk;
    if (trunk == 0) return tips;
    mean /= double(trunk);
    uint32_t centre = 0;
    double nearest = kInfinity;
    for (uint32_t v = 0; v < vertices.size(); ++v)
        if (parts[v] == kNoTip && (vertices[v] - mean).squaredNorm() < nearest) nearest = (vertices[v] - mean).squaredNorm(), centre = v;
    std::vector<uint32_t> towards_centre;
    const std::vector<double> from_centre = geodesic_from(g, {centre}, &towards_centre);
    // Among the part's vertices at least kTipReach of its farthest from the centre in space, the
    // one farthest along the surface: the crown, a fingertip, the toes (the mesh's inner surfaces,
    // the mouth and eye sockets, lie far along it but not in space).
    for (std::size_t t = 0; t < kTipCount; ++t) {
        double reach = 0, far = -1;
        for (uint32_t v = 0; v < vertices.size(); ++v)
            if (parts[v] == t) reach = std::max(reach, (vertices[v] - vertices[centre]).norm());
        for (uint32_t v = 0; v < vertices.size(); ++v)
            if (parts[v] == t && std::isfinite(from_centre[v]) && from_centre[v] > far && (vertices[v] - vertices[centre]).norm() >= kTipReach * reach)
                far = from_centre[v], tips.vertex[t] = v;
        if (far < 0) return tips;
        // The guide: the hands' kPalmBack back along the path to the centre.
        tips.guide[t] = tips.vertex[t];
        if (t == 1 || t == 2)
            for (uint32_t v = tips.vertex[t]; towards_centre[v] != v && from_centre[tips.vertex[t]] - from_centre[v] < kPalmBack; v = towards_centre[v])
                tips.guide[t] = towards_centre[v];
    }
    for (std::size_t a = 0; a < kTipCount; ++a) {
        const std::vector<double> d = geodesic_from(g, {tips.vertex[a]});
        for (std::size_t b = 0; b < kTipCount; ++b) tips.geodesic(Eigen::Index(a), Eigen::Index(b)) = d[tips.vertex[b]];
    }
    tips.valid = tips.geodesic.allFinite();
    return tips;
}

std::vector<TipLabelling> label_extremities(const ScanExtremities& scan, const ModelTips& model, std::size_t keep) {
    std::vector<TipLabelling> all;
    const int n = int(scan.points.size());
    if (!model.valid || n < int(kMinTips)) return all;
    // Every injective assignment of the tips to extremities or to none, with at least kMinTips
    // assigned: (n + 1)^5 tries, about 17,000 for 6 extremities.
    std::array<int, kTipCount> a{};
    const std::function<void(std::size_t)> assign = [&](std::size_t t) {
        if (t == kTipCount) {
            std::size_t found = 0;
            for (int e : a) found += e >= 0;
            if (found < kMinTips) return;
            // The scale that best maps the model's geodesics onto the scan's, then the mismatch.
            double ab = 0, bb = 0;
            for (std::size_t i = 0; i < kTipCount; ++i)
                for (std::size_t j = i + 1; j < kTipCount; ++j) {
                    if (a[i] < 0 || a[j] < 0) continue;
                    const double s = scan.geodesic(a[i], a[j]), m = model.geodesic(Eigen::Index(i), Eigen::Index(j));
                    ab += s * m, bb += m * m;
                }
            if (bb <= 0) return;
            const double scale = std::clamp(ab / bb, kMinScale, kMaxScale);
            double cost = 0;
            std::size_t pairs = 0;
            for (std::size_t i = 0; i < kTipCount; ++i)
                for (std::size_t j = i + 1; j < kTipCount; ++j) {
                    if (a[i] < 0 || a[j] < 0) continue;
                    const double m = scale * model.geodesic(Eigen::Index(i), Eigen::Index(j));
                    const double r = (scan.geodesic(a[i], a[j]) - m) / m;
                    cost += r * r, ++pairs;
                }
            TipLabelling l;
            l.extremity = a, l.scale = scale;
            // Shortcuts where parts touch shrink a scan's geodesics: a labelling that needs the
            // scan much smaller than the model's mean body pays for it.
            const double shrunk = std::max(0.0, (kUsualScale - scale) / kScaleSpread);
            l.cost = cost / double(pairs) + kMissingTip * double(kTipCount - found) + kScalePenalty * shrunk * shrunk;
            if (std::isfinite(l.cost) && l.cost <= kMaxLabelCost) all.push_back(l);
            return;
        }
        for (int e = -1; e < n; ++e) {
            bool used = false;
            for (std::size_t u = 0; u < t && e >= 0; ++u) used |= a[u] == e;
            if (used) continue;
            a[t] = e;
            assign(t + 1);
        }
    };
    assign(0);
    std::stable_sort(all.begin(), all.end(), [](const TipLabelling& x, const TipLabelling& y) { return x.cost < y.cost; });
    // The best, each with its mirror images, until `keep`.
    std::vector<TipLabelling> kept;
    const auto has = [&](const std::array<int, kTipCount>& e) {
        return std::any_of(kept.begin(), kept.end(), [&](const TipLabelling& k) { return k.extremity == e; });
    };
    for (const TipLabelling& l : all) {
        if (kept.size() >= keep) break;
        if (has(l.extremity)) continue;
        // Itself, its mirror image (a person facing the other way), then one side pair swapped.
        for (const int swap : {0, 3, 1, 2}) {
            if (kept.size() >= keep) break;
            TipLabelling m = l;
            if (swap & 1) std::swap(m.extremity[1], m.extremity[2]);
            if (swap & 2) std::swap(m.extremity[3], m.extremity[4]);
            if (!has(m.extremity)) kept.push_back(m);
        }
    }
    return kept;
}

}  // namespace ssc::fitting
