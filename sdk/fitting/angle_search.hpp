// The search shared by the fitter's searches over a few anatomical angles (head_search.cpp,
// wrist_search.cpp): a grid of candidates scored in parallel, the best two refined by a
// coordinate pattern search within the joints' ranges at 10, 5 and 2.5 degrees.
#pragma once

#include "common/thread_pool.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ssc::fitting {

template <std::size_t N>
struct AngleCandidate {
    std::array<double, N> a{};  // radians
    double score = 0;
};

// grid[0]: the fit's angles with their score; the rest are scored here, each stopping at twice
// that (score(worker, angles, bound) may return anything >= bound once it cannot beat it). A step
// needs only to know whether a neighbour beats the candidate, so its scoring stops at the
// candidate's score. lo, hi: each angle's range. Returns the best candidate found.
template <std::size_t N, class Score>
AngleCandidate<N> search_angles(std::vector<AngleCandidate<N>> grid, const std::array<double, N>& lo, const std::array<double, N>& hi,
                                ThreadPool& pool, const Score& score) {
    const double current = grid[0].score;
    const auto by_score = [](const AngleCandidate<N>& x, const AngleCandidate<N>& y) { return x.score < y.score; };
    pool.parallel_for(grid.size() - 1, [&](std::size_t i, unsigned w) { grid[i + 1].score = score(w, grid[i + 1].a, 2 * current); });
    std::stable_sort(grid.begin(), grid.end(), by_score);
    grid.resize(std::min<std::size_t>(grid.size(), 2));
    auto refine = [&](AngleCandidate<N>& x, double step, unsigned w) {
        for (bool improved = true; improved;) {
            improved = false;
            for (std::size_t c = 0; c < N; ++c)
                for (double sign : {1.0, -1.0}) {
                    AngleCandidate<N> y = x;
                    y.a[c] = std::clamp(y.a[c] + sign * step, lo[c], hi[c]);
                    if (y.a[c] == x.a[c]) continue;
                    y.score = score(w, y.a, x.score);
                    if (y.score < x.score) x = y, improved = true;
                }
        }
    };
    constexpr double d = M_PI / 180;
    pool.parallel_for(grid.size(), [&](std::size_t i, unsigned w) {
        for (double step : {10 * d, 5 * d, 2.5 * d}) refine(grid[i], step, w);
    });
    return *std::min_element(grid.begin(), grid.end(), by_score);
}

}  // namespace ssc::fitting
