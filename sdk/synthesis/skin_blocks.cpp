#include "skin_blocks.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace ssc {

namespace {

constexpr uint32_t L = SkinBlocks::kLanes;

// One block's entries, before ordering.
struct Entry {
    uint32_t offset;
    uint16_t lanes;
    std::array<float, L> weights;
};

std::vector<Entry> block_entries(uint32_t V, uint32_t b, const uint16_t* joints, const float* weights) {
    // A vertex's influence is keyed by (joint, how many times the vertex named that joint before),
    // so that keys sort as SkinLayout orders a vertex's influences.
    using Key = std::pair<uint32_t, uint32_t>;
    std::vector<std::pair<Key, std::pair<uint32_t, float>>> influences;  // (key, (lane, weight))
    for (uint32_t l = 0; l < L && L * b + l < V; ++l) {
        const std::size_t v = std::size_t(L) * b + l;
        std::array<uint16_t, 4> named{};
        uint32_t count = 0;
        for (int i = 0; i < 4; ++i) {
            const float w = weights[4 * v + std::size_t(i)];
            if (w <= 0.f) continue;
            const uint16_t j = joints[4 * v + std::size_t(i)];
            uint32_t before = 0;
            for (uint32_t k = 0; k < count; ++k) before += named[k] == j;
            named[count++] = j;
            influences.push_back({{j, before}, {l, w}});
        }
    }
    std::vector<Key> keys;
    for (const auto& e : influences) keys.push_back(e.first);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<Entry> entries(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) entries[k] = Entry{16u * keys[k].first, 0, {}};
    for (const auto& e : influences) {
        Entry& to = entries[std::size_t(std::lower_bound(keys.begin(), keys.end(), e.first) - keys.begin())];
        to.lanes = uint16_t(to.lanes | (1u << e.second.first));
        to.weights[e.second.first] = e.second.second;
    }
    return entries;
}

bool unit(const std::vector<Entry>& entries) {
    if (entries.size() != 1 || entries[0].lanes != 0xFFFF) return false;
    return std::all_of(entries[0].weights.begin(), entries[0].weights.end(), [](float w) { return w == 1.f; });
}

}  // namespace

SkinBlocks build_skin_blocks(uint32_t V, const uint16_t* joints, const float* weights, const Allocator* alloc) {
    SkinBlocks s;
    s.vertex_count = V;
    s.first = Vec<uint32_t>(CAlloc<uint32_t>(alloc));
    s.unit = Vec<uint8_t>(CAlloc<uint8_t>(alloc));
    s.offsets = Vec<uint32_t>(CAlloc<uint32_t>(alloc));
    s.lanes = Vec<uint16_t>(CAlloc<uint16_t>(alloc));
    s.weights = Vec<float>(CAlloc<float>(alloc));
    for (uint32_t b = 0; b < s.block_count(); ++b) {
        const std::vector<Entry> entries = block_entries(V, b, joints, weights);
        s.first.push_back(uint32_t(s.offsets.size()));
        s.unit.push_back(unit(entries));
        for (const Entry& e : entries) {
            s.offsets.push_back(e.offset);
            s.lanes.push_back(e.lanes);
            s.weights.insert(s.weights.end(), e.weights.begin(), e.weights.end());
        }
    }
    s.first.push_back(uint32_t(s.offsets.size()));
    return s;
}

}  // namespace ssc
