#include "skin_layout.hpp"

#include <algorithm>

namespace ssc {

SkinLayout build_skin_layout(uint32_t V, const uint16_t* joints, const float* weights, const Allocator* alloc) {
    // Per vertex: its influences with weight > 0, sorted by joint (the run key).
    struct Entry {
        uint32_t vertex, n;
        uint16_t joints[4];
        float weights[4];
    };
    std::vector<Entry> entries(V);
    for (uint32_t v = 0; v < V; ++v) {
        Entry& e = entries[v];
        e = Entry{v, 0, {0, 0, 0, 0}, {0, 0, 0, 0}};
        for (int i = 0; i < 4; ++i) {
            const float w = weights[4 * std::size_t(v) + std::size_t(i)];
            if (w <= 0.f) continue;
            uint32_t at = e.n++;
            while (at > 0 && e.joints[at - 1] > joints[4 * std::size_t(v) + std::size_t(i)]) {  // insertion sort
                e.joints[at] = e.joints[at - 1];
                e.weights[at] = e.weights[at - 1];
                --at;
            }
            e.joints[at] = joints[4 * std::size_t(v) + std::size_t(i)];
            e.weights[at] = w;
        }
    }
    auto key_less = [](const Entry& a, const Entry& b) {
        if (a.n != b.n) return a.n < b.n;
        for (uint32_t i = 0; i < a.n; ++i)
            if (a.joints[i] != b.joints[i]) return a.joints[i] < b.joints[i];
        return false;
    };
    std::stable_sort(entries.begin(), entries.end(), key_less);

    SkinLayout s;
    s.vertex_count = V;
    s.vertices = Vec<uint32_t>(CAlloc<uint32_t>(alloc));
    for (auto& w : s.weights) w = Vec<float>(CAlloc<float>(alloc));
    s.contiguous = Vec<uint8_t>(CAlloc<uint8_t>(alloc));
    s.first_slot = Vec<uint32_t>(V, 0u, CAlloc<uint32_t>(alloc));
    for (std::size_t first = 0; first < entries.size();) {
        std::size_t last = first + 1;
        while (last < entries.size() && !key_less(entries[first], entries[last])) ++last;
        SkinLayout::Run run{};
        run.begin = static_cast<uint32_t>(s.vertices.size());
        run.influences = entries[first].n;
        for (uint32_t i = 0; i < run.influences; ++i) run.offsets[i] = 16u * entries[first].joints[i];
        const std::size_t padded = (last - first + SkinLayout::kBlock - 1) / SkinLayout::kBlock * SkinLayout::kBlock;
        for (std::size_t k = 0; k < padded; ++k) {
            const Entry& e = entries[std::min(first + k, last - 1)];
            s.vertices.push_back(e.vertex);
            for (int i = 0; i < 4; ++i) s.weights[i].push_back(e.weights[i]);
        }
        run.end = static_cast<uint32_t>(s.vertices.size());
        s.runs.push_back(run);
        first = last;
    }
    for (std::size_t b = 0; b < s.vertices.size(); b += SkinLayout::kBlock) {
        bool contiguous = true;
        for (uint32_t i = 1; i < SkinLayout::kBlock; ++i) contiguous &= s.vertices[b + i] == s.vertices[b] + i;
        s.contiguous.push_back(contiguous);
    }
    for (uint32_t slot = s.slot_count(); slot-- > 0;) s.first_slot[s.vertices[slot]] = slot;
    return s;
}

}  // namespace ssc
