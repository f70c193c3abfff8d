#include "fitting/correspondences.hpp"

#include "fitting/robust.hpp"

namespace ssc::fitting {

std::size_t find_pairs(const CloudView& cloud, const PosedModel& model, const PairGate& gate, ThreadPool& pool,
                       std::vector<Pair>& out) {
    const std::vector<Vector3d>& points = *cloud.points;
    const std::vector<Vector3d>& normals = *cloud.normals;
    const std::vector<double>& confidence = *cloud.confidence;
    const std::vector<uint32_t>& scan_sample = *cloud.sample;
    const std::vector<Vector3d>& posed = *model.vertices;
    const std::vector<Vector3d>& posed_normals = *model.normals;
    const std::vector<uint32_t>& vertex_sample = *model.sample;
    const GridIndex& model_index = *model.index;
    const double max2 = gate.max_distance * gate.max_distance;
    auto compatible = [&](const Vector3d& scan_n, const Vector3d& model_n) {
        return normals_agree(scan_n, model_n, cloud.oriented, gate.min_normal_dot);
    };
    using Found = std::vector<std::pair<double, Pair>>;
    constexpr std::size_t kChunks = 8;
    Found chunks[2][kChunks];
    auto scan_to_model = [&](std::size_t s, Found& found) {
        const uint32_t i = scan_sample[s];
        double d2;
        const uint32_t nearest = model_index.nearest(points[i], gate.max_distance, &d2);
        if (nearest == GridIndex::kNone) return;
        const uint32_t v = model.dense ? nearest : vertex_sample[nearest];
        if (!compatible(normals[i], posed_normals[v]) || confidence[i] <= 0) return;
        Pair p;
        p.model.vertex[0] = v;
        p.target = points[i];
        p.normal = posed_normals[v];  // the model's normal: always known and oriented
        p.weight = confidence[i];
        found.emplace_back(d2, p);
    };
    auto model_to_scan = [&](std::size_t s, Found& found) {
        const uint32_t v = vertex_sample[s];
        double d2;
        const uint32_t i = cloud.grid->nearest(posed[v], gate.max_distance, &d2);
        if (i == GridIndex::kNone || !compatible(normals[i], posed_normals[v]) || confidence[i] <= 0) return;
        // Holes: a model vertex over a hole in the scan finds the nearest point at the hole's
        // edge, which belongs to another part of the model and would drag this part onto it
        // (a hand in a hole curls onto the wrist). Such a point's own nearest model point is
        // far from the vertex: the pair is kept only if the two agree to within a fraction of
        // the gate. (Both lie within the pair's distance of the scan point, so pairs closer
        // than half that fraction pass without the query.)
        const double agree2 = kReciprocal * kReciprocal * max2;
        if (4 * d2 > agree2) {
            const uint32_t back = model_index.nearest(points[i], gate.max_distance, nullptr);
            if (back == GridIndex::kNone || (posed[model.dense ? back : vertex_sample[back]] - posed[v]).squaredNorm() > agree2) return;
        }
        Pair p;
        p.model.vertex[0] = v;
        p.target = points[i];
        p.normal = normals[i].squaredNorm() > 0 ? normals[i] : posed_normals[v];
        p.weight = 0.5 * confidence[i];  // the two directions share one budget
        found.emplace_back(d2, p);
    };
    const std::size_t count[2] = {gate.scan_points, gate.model_points};
    pool.parallel_for(2 * kChunks, [&](std::size_t item, unsigned) {
        const std::size_t d = item / kChunks, c = item % kChunks;
        for (std::size_t s = c * count[d] / kChunks; s < (c + 1) * count[d] / kChunks; ++s)
            d == 0 ? scan_to_model(s, chunks[d][c]) : model_to_scan(s, chunks[d][c]);
    });
    std::vector<Pair> kept[2];
    pool.parallel_for(2, [&](std::size_t d, unsigned) {
        Found found;
        for (const Found& c : chunks[d]) found.insert(found.end(), c.begin(), c.end());
        std::vector<double> scratch;
        append_trimmed(found, scratch, kept[d]);
    });
    out.insert(out.end(), kept[0].begin(), kept[0].end());
    out.insert(out.end(), kept[1].begin(), kept[1].end());
    return count[0] + count[1];
}

}  // namespace ssc::fitting
