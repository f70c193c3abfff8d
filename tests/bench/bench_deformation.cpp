// The registration's deformation system on the default model's template (13,380 vertices: 53,520
// unknowns): one factorisation and one solve of its block Cholesky, alone and on two threads.
// A registration of a booth scan factorises 7 times and solves about 17 times.
#include "capi/cpp_access.hpp"
#include "common/thread_pool.hpp"
#include "registration/nonrigid.hpp"

#include <sscape/sscape.h>

#include <benchmark/benchmark.h>

#include <random>
#include <stdexcept>
#include <vector>

namespace {

using ssc::registration::NonrigidSystem;

// The default template at rest, its system, and targets and weights as a registration's rounds
// give them (a fifth of the vertices without data).
struct Problem {
    std::vector<Eigen::Vector3d> targets;
    std::vector<double> weights;
    std::unique_ptr<NonrigidSystem> system;
    Problem() {
        ssc_model* model = nullptr;
        ssc_body* body = nullptr;
        if (ssc_model_load_default(nullptr, &model) != SSC_OK || ssc_body_create(model, nullptr, &body) != SSC_OK)
            throw std::runtime_error(ssc_last_error());
        const uint32_t V = ssc_model_vertex_count(model);
        std::vector<float> rest(3ull * V);
        if (ssc_body_get_vertices(body, rest.data(), V, 0) != SSC_OK) throw std::runtime_error(ssc_last_error());
        std::vector<Eigen::Vector3d> vertices(V);
        for (uint32_t v = 0; v < V; ++v) vertices[v] = Eigen::Vector3d(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
        const auto& mesh = ssc::model_of(model).data().mesh;
        const std::vector<uint32_t> triangles(mesh.triangles.begin(), mesh.triangles.end());
        system = std::make_unique<NonrigidSystem>(vertices, ssc::registration::mesh_edges(triangles, V), std::vector<double>{},
                                                  std::vector<ssc::registration::TemplatePoint>{});
        std::mt19937 rng(1);
        std::normal_distribution<double> n(0, 0.005);
        for (uint32_t v = 0; v < V; ++v) {
            targets.push_back(vertices[v] + Eigen::Vector3d(n(rng), n(rng), n(rng)));
            weights.push_back(rng() % 5 ? 1.0 : 0.0);
        }
        ssc_body_destroy(body);
        ssc_model_release(model);
    }
};

Problem& problem() {
    static Problem p;
    return p;
}

const ssc::registration::EnergyWeights kWeights{1.0, 0.03, 0.0};

// Arg: threads (1: no pool).
void BM_Factorize(benchmark::State& state) {
    Problem& p = problem();
    ssc::ThreadPool pool(unsigned(state.range(0)));
    for (auto _ : state) p.system->factorize(kWeights, p.weights, {}, state.range(0) > 1 ? &pool : nullptr);
}

void BM_Solve(benchmark::State& state) {
    Problem& p = problem();
    ssc::ThreadPool pool(unsigned(state.range(0)));
    p.system->factorize(kWeights, p.weights, {});
    const Eigen::MatrixX3d start = p.system->identity();
    for (auto _ : state) {
        Eigen::MatrixX3d X = p.system->solve(p.targets, {}, start, state.range(0) > 1 ? &pool : nullptr);
        benchmark::DoNotOptimize(X.data());
    }
}

}  // namespace

BENCHMARK(BM_Factorize)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Solve)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
