// Runtime benchmarks on a procedural model of the default model's size (13,380 vertices,
// 53 joints, 50 components). Targets on the 2-core dev machine: load <= 20 ms, pose-only
// <= 30 us, shape + pose <= 150 us (one thread), batch >= 15,000 bodies/s.
#include "capi/handles.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/cpu.hpp"
#include "synthesis/kernels.hpp"
#include "synthesis/kernels_skin_xyz.hpp"
#include "testing/synthetic_model.hpp"

#include <sscape/sscape.h>

#include <benchmark/benchmark.h>
#include <zstd.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace {

const std::vector<unsigned char>& model_bytes() {
    static const std::vector<unsigned char> bytes = [] {
        ssc::testing::SyntheticSpec spec;  // defaults: humanoid, 13,380 vertices, 50 components
        return ssc::format::write_model(ssc::testing::build_synthetic_model(spec).data);
    }();
    return bytes;
}

ssc_model* load(ssc_context* ctx = nullptr) {
    ssc_model* m = nullptr;
    if (ssc_model_load_memory(ctx, model_bytes().data(), model_bytes().size(), &m) != SSC_OK)
        throw std::runtime_error(ssc_last_error());
    return m;
}

// A pool of random parameters so successive iterations differ (no caching effects).
struct Params {
    std::vector<std::vector<float>> shapes, poses;
    Params(uint32_t K, uint32_t J, int n = 64) {
        std::mt19937 rng(42);
        std::normal_distribution<float> normal;
        for (int i = 0; i < n; ++i) {
            std::vector<float> s(K), p(3ull * J);
            for (auto& c : s) c = normal(rng);
            for (auto& c : p) c = 0.3f * normal(rng);
            shapes.push_back(s);
            poses.push_back(p);
        }
    }
};

ssc_model* load_default() {
    ssc_model* m = nullptr;
    if (ssc_model_load_default(nullptr, &m) != SSC_OK) throw std::runtime_error(ssc_last_error());
    return m;
}

// One body on the benchmark model (or the shipped default model), with a pool of parameters and
// an output buffer.
struct OneBody {
    ssc_model* m;
    ssc_body* b = nullptr;
    uint32_t V = ssc_model_vertex_count(m), J = ssc_model_joint_count(m), K = ssc_model_shape_count(m);
    Params p{K, J};
    std::vector<float> out = std::vector<float>(3ull * V);
    OneBody(const OneBody&) = delete;
    explicit OneBody(bool shipped = false) : m(shipped ? load_default() : load()) { ssc_body_create(m, nullptr, &b); }
    ~OneBody() {
        ssc_body_destroy(b);
        ssc_model_release(m);
    }
};

void BM_Load(benchmark::State& state) {
    model_bytes();
    for (auto _ : state) {
        ssc_model* m = load();
        benchmark::DoNotOptimize(m);
        ssc_model_release(m);
    }
    state.counters["file_bytes"] = double(model_bytes().size());
}

void BM_PoseOnly(benchmark::State& state) {
    OneBody f(state.range(0) != 0);
    ssc_body_set_shape(f.b, f.p.shapes[0].data(), f.K);
    ssc_body_get_vertices(f.b, f.out.data(), f.V, 0);  // shape stage done once, outside the loop
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_vertices(f.b, f.out.data(), f.V, 0);
        benchmark::ClobberMemory();
    }
}

// A level's description, or the benchmark skipped for a level the model lacks.
bool level_info(benchmark::State& state, const ssc_model* m, uint32_t level, ssc_level_info& info) {
    if (level >= ssc_model_level_count(m)) {
        state.SkipWithError("the default model has no such level");
        return false;
    }
    info.struct_size = sizeof info;
    ssc_model_get_level_info(m, level, &info);
    return true;
}

// Pose-only synthesis of one level of detail of the shipped default model (0: the full mesh), its
// vertices copied out: what an engine pays per frame for a far body.
void BM_PoseOnlyLevel(benchmark::State& state) {
    OneBody f(true);
    const uint32_t level = uint32_t(state.range(0));
    ssc_level_info info{};
    if (!level_info(state, f.m, level, info)) return;
    ssc_body_set_shape(f.b, f.p.shapes[0].data(), f.K);
    ssc_body_get_level_vertices(f.b, level, f.out.data(), info.vertex_count, 0);  // shape stage done once
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_level_vertices(f.b, level, f.out.data(), info.vertex_count, 0);
        benchmark::ClobberMemory();
    }
    state.SetLabel(std::string(info.name) + ", " + std::to_string(info.vertex_count) + " vertices");
}

// The part of pose-only synthesis no level saves: the pose set and the skeleton (53 joints' world
// and skinning matrices), no vertex.
void BM_PoseOnlySkeleton(benchmark::State& state) {
    OneBody f(true);
    ssc_body_set_shape(f.b, f.p.shapes[0].data(), f.K);
    ssc_body_get_vertices(f.b, f.out.data(), f.V, 0);
    std::vector<float> matrices(16ull * f.J);
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_skinning_matrices(f.b, matrices.data(), f.J);
        benchmark::ClobberMemory();
    }
}

void BM_ShapeAndPose(benchmark::State& state) {
    OneBody f(state.range(0) != 0);
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_shape(f.b, f.p.shapes[i % f.p.shapes.size()].data(), f.K);
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_vertices(f.b, f.out.data(), f.V, 0);
        benchmark::ClobberMemory();
    }
}

// Shape and pose of one level of detail of the default model, its vertices copied out: a new body
// variant each iteration (the browser benchmark, tests/web/bench.mjs, runs the same in WebAssembly).
void BM_ShapeAndPoseLevel(benchmark::State& state) {
    OneBody f(true);
    const uint32_t level = uint32_t(state.range(0));
    ssc_level_info info{};
    if (!level_info(state, f.m, level, info)) return;
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_shape(f.b, f.p.shapes[i % f.p.shapes.size()].data(), f.K);
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_level_vertices(f.b, level, f.out.data(), info.vertex_count, 0);
        benchmark::ClobberMemory();
    }
    state.SetLabel(std::string(info.name) + ", " + std::to_string(info.vertex_count) + " vertices");
}

void BM_Normals(benchmark::State& state) {
    OneBody f;
    std::size_t i = 0;
    for (auto _ : state) {
        ssc_body_set_pose_axis_angle(f.b, f.p.poses[i++ % f.p.poses.size()].data(), f.J, nullptr);
        ssc_body_get_normals(f.b, f.out.data(), f.V, 0);  // includes the pose update
        benchmark::ClobberMemory();
    }
}

void BM_Batch(benchmark::State& state) {
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    def.worker_count = static_cast<uint32_t>(state.range(0));
    ssc_context* ctx = nullptr;
    ssc_context_create(&def, &ctx);
    ssc_model* m = load(ctx);
    const uint32_t V = ssc_model_vertex_count(m), J = ssc_model_joint_count(m), K = ssc_model_shape_count(m);
    const uint32_t n = 256;
    Params p(K, J, n);
    std::vector<float> shapes, poses, out(std::size_t(n) * 3 * V);
    for (uint32_t i = 0; i < n; ++i) {
        shapes.insert(shapes.end(), p.shapes[i].begin(), p.shapes[i].end());
        poses.insert(poses.end(), p.poses[i].begin(), p.poses[i].end());
    }
    ssc_batch_desc d;
    ssc_batch_desc_init(&d, sizeof d);
    d.body_count = n;
    d.shapes = shapes.data();
    d.shape_count = K;
    d.pose_format = SSC_ROTATION_AXIS_ANGLE;
    d.poses = poses.data();
    d.vertices = out.data();
    d.vertices_capacity = std::size_t(n) * V;
    for (auto _ : state) {
        if (ssc_model_synthesize_batch(m, &d) != SSC_OK) state.SkipWithError(ssc_last_error());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * n);
    ssc_model_release(m);
    ssc_context_destroy(ctx);
}

// The memory floor of one shape update: only reading a 16-bit basis of the benchmark model's size
// (3V x K values, 4.0 MB, larger than L2), with no arithmetic.
#if defined(__x86_64__)
SSC_TARGET_AVX2_BEGIN
// One 3x4 matrix applied to contiguous planar positions, in and out: the memory floor of any
// skinning over these arrays on this machine (AVX2).
[[gnu::noinline]] void transform_stream(const float* rest, float* out, uint32_t V, const float* M) {
    __m256 k[15];
    for (int e = 0; e < 15; ++e) k[e] = _mm256_broadcast_ss(M + e);
    auto row = [&](__m256 x, __m256 y, __m256 z, int a, int b, int c, int d) {
        return _mm256_add_ps(_mm256_fmadd_ps(k[c], z, _mm256_mul_ps(k[a], x)), _mm256_fmadd_ps(k[b], y, k[d]));
    };
    for (uint32_t v = 0; v + 8 <= V; v += 8) {
        const __m256 x = _mm256_loadu_ps(rest + v), y = _mm256_loadu_ps(rest + V + v), z = _mm256_loadu_ps(rest + 2 * V + v);
        _mm256_storeu_ps(out + v, row(x, y, z, 0, 4, 8, 12));
        _mm256_storeu_ps(out + V + v, row(x, y, z, 1, 5, 9, 13));
        _mm256_storeu_ps(out + 2 * V + v, row(x, y, z, 2, 6, 10, 14));
    }
}
SSC_TARGET_END
#endif

// The stages of a posed body's vertices, alone, on the default model (issue 51's profile; see
// docs/speed.md): 0 skinning in vertex order (a shape's first posing), 1 the rest put in slot
// order (once per shape), 2 skinning in slot order (every later posing), 3 slot order to the
// caller's xyz, 4 planar vertex order to xyz, 5 the memory floor (transform_stream), 6 the shape
// stage's rows for one body (against BM_BasisReadFloor), 7 slot order skinned into xyz as well, 8
// and 9 skinning in vertex order by blocks of 16 and their joints (skin_blocks.hpp), planar, and
// planar and xyz (what a body does on AVX-512).
void BM_PoseStage(benchmark::State& state) {
    namespace k = ssc::kernels;
    OneBody f(true);
    ssc_body_set_shape(f.b, f.p.shapes[0].data(), f.K);
    ssc_body_set_pose_axis_angle(f.b, f.p.poses[1].data(), f.J, nullptr);
    ssc_body_get_vertices(f.b, f.out.data(), f.V, 0);
    ssc::Body& body = f.b->body;
    const ssc::SkinLayout& layout = f.m->model.skin_layout();
    const ssc::SkinBlocks& blocks = f.m->model.skin_blocks();
    const uint32_t S = layout.slot_count(), V = f.V;
    const float* rest = body.rest_planar();
    const k::SkinMatrix* skinning = body.skinning();
    std::vector<float> rest_slots(3ull * S), slots(3ull * S), planar(3ull * V);
    k::to_slot_order(layout, rest, rest_slots.data(), 0, S);
    k::skin_slots_in_slot_order(layout, rest_slots.data(), skinning, slots.data(), 0, S, k::active_isa());
    const int stage = int(state.range(0));
    static const char* names[] = {"skin, vertex order", "rest to slot order", "skin, slot order", "slot order to xyz", "planar to xyz",
                                  "one matrix, contiguous (floor)", "shape rows, one body", "skin, slot order, and xyz", "skin blocks, vertex order",
                                  "skin blocks, vertex order, and xyz"};
    const ssc::Model& model = f.m->model;
    std::vector<float> scaled(model.component_count()), shaped(model.padded_rows());
    k::scale_coefficients(model, f.p.shapes[0].data(), scaled.data());
    const float* scaled_rows = scaled.data();
    float* shaped_rows = shaped.data();
    for (auto _ : state) {
        switch (stage) {
            case 0: k::skin_slots(layout, rest, skinning, planar.data(), 0, S, k::active_isa()); break;
            case 1: k::to_slot_order(layout, rest, rest_slots.data(), 0, S); break;
            case 2: k::skin_slots_in_slot_order(layout, rest_slots.data(), skinning, slots.data(), 0, S, k::active_isa()); break;
            case 3: k::slots_to_xyz(layout, slots.data(), f.out.data(), 12, 0, V); break;
            case 4: k::planar_to_xyz(planar.data(), V, f.out.data(), 12); break;
            case 6: k::shape_rows(model, 1, &scaled_rows, &shaped_rows, 0, model.padded_rows() / ssc::Model::kChunk); break;
            case 7: k::skin_slots_and_xyz(layout, rest_slots.data(), skinning, slots.data(), f.out.data(), 0, S, k::active_isa()); break;
            case 8: k::skin_blocks(blocks, rest, skinning, planar.data(), nullptr, 0, blocks.block_count(), k::active_isa()); break;
            case 9: k::skin_blocks(blocks, rest, skinning, planar.data(), f.out.data(), 0, blocks.block_count(), k::active_isa()); break;
            default:
#if defined(__x86_64__)
                transform_stream(rest, planar.data(), V, skinning[3].m);
#endif
                break;
        }
        benchmark::ClobberMemory();
    }
    state.SetLabel(names[stage]);
}

#if defined(__x86_64__)
// The default model's 16-bit basis read as fast as the widest vector loads this CPU has can
// stream it (four independent XOR accumulators, nothing converted or multiplied): the floor under
// the shape stage (BM_PoseStage/6) on this machine.
__attribute__((target("avx2,avx512f"))) uint64_t xor_stream_avx512(const int16_t* q, std::size_t n) {
    __m512i a = _mm512_setzero_si512(), b = a, c = a, d = a;
    std::size_t i = 0;
    for (; i + 128 <= n; i += 128) {
        a = _mm512_xor_si512(a, _mm512_loadu_si512(q + i));
        b = _mm512_xor_si512(b, _mm512_loadu_si512(q + i + 32));
        c = _mm512_xor_si512(c, _mm512_loadu_si512(q + i + 64));
        d = _mm512_xor_si512(d, _mm512_loadu_si512(q + i + 96));
    }
    alignas(64) uint64_t lanes[8];
    _mm512_store_si512(lanes, _mm512_xor_si512(_mm512_xor_si512(a, b), _mm512_xor_si512(c, d)));
    return lanes[0] ^ lanes[7];
}
SSC_TARGET_AVX2_BEGIN
uint64_t xor_stream_avx2(const int16_t* q, std::size_t n) {
    __m256i a = _mm256_setzero_si256(), b = a, c = a, d = a;
    std::size_t i = 0;
    for (; i + 64 <= n; i += 64) {
        a = _mm256_xor_si256(a, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q + i)));
        b = _mm256_xor_si256(b, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q + i + 16)));
        c = _mm256_xor_si256(c, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q + i + 32)));
        d = _mm256_xor_si256(d, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q + i + 48)));
    }
    alignas(32) uint64_t lanes[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), _mm256_xor_si256(_mm256_xor_si256(a, b), _mm256_xor_si256(c, d)));
    return lanes[0] ^ lanes[3];
}
SSC_TARGET_END
#endif

void BM_BasisReadFloor(benchmark::State& state) {
    OneBody f(true);
    const ssc::Model& model = f.m->model;
    const int16_t* q = model.basis_panels();
    const std::size_t n = model.padded_rows() * model.component_count();
    const ssc::kernels::Isa isa = ssc::kernels::active_isa();
    for (auto _ : state) {
#if defined(__x86_64__)
        if (isa == ssc::kernels::Isa::Avx512) {
            uint64_t r = xor_stream_avx512(q, n);
            benchmark::DoNotOptimize(r);
            continue;
        }
        if (isa == ssc::kernels::Isa::Avx2) {
            uint64_t r = xor_stream_avx2(q, n);
            benchmark::DoNotOptimize(r);
            continue;
        }
#endif
        uint16_t sum = 0;  // wrapping 16-bit sum
        for (std::size_t i = 0; i < n; ++i) sum = uint16_t(sum + uint16_t(q[i]));
        benchmark::DoNotOptimize(sum);
    }
    state.SetLabel(ssc::kernels::isa_name(isa));
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(n * sizeof(int16_t)));
}

}  // namespace

BENCHMARK(BM_BasisReadFloor)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseStage)->DenseRange(0, 9)->Unit(benchmark::kMicrosecond);
void BM_LoadDefaultModel(benchmark::State& state) {
    for (auto _ : state) {
        ssc_model* m = load_default();
        benchmark::DoNotOptimize(m);
        ssc_model_release(m);
    }
}

// What bounds a load (issue 51): zstd alone decompressing the built-in model's frame (14.4 MB of
// content for its 2.2 MB) into a buffer already in memory, no checks, no decoding.
void BM_LoadZstdFloor(benchmark::State& state) {
    const void* data = nullptr;
    std::size_t size = 0;
    if (ssc_default_model_file(&data, &size) != SSC_OK) return state.SkipWithError(ssc_last_error());
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t frame = 0;  // the zstd frame's magic number, after the container's header
    while (frame + 4 < size && !(p[frame] == 0x28 && p[frame + 1] == 0xB5 && p[frame + 2] == 0x2F && p[frame + 3] == 0xFD)) ++frame;
    const unsigned long long content = ZSTD_getFrameContentSize(p + frame, size - frame);
    if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN) return state.SkipWithError("no zstd frame");
    std::vector<unsigned char> out(content);
    ZSTD_DCtx* dctx = ZSTD_createDCtx();
    for (auto _ : state) {
        if (ZSTD_isError(ZSTD_decompressDCtx(dctx, out.data(), out.size(), p + frame, size - frame))) state.SkipWithError("zstd failed");
        benchmark::ClobberMemory();
    }
    ZSTD_freeDCtx(dctx);
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(content));
}

// The same model from its file on disk: what the built-in one is compared with (issue 51).
void BM_LoadDefaultFile(benchmark::State& state) {
    for (auto _ : state) {
        ssc_model* m = nullptr;
        if (ssc_model_load_file(nullptr, SSCAPE_DEFAULT_MODEL_FILE, &m) != SSC_OK) state.SkipWithError(ssc_last_error());
        benchmark::DoNotOptimize(m);
        ssc_model_release(m);
    }
}

BENCHMARK(BM_Load)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadDefaultModel)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadZstdFloor)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadDefaultFile)->Unit(benchmark::kMillisecond);
// Arg 0: the procedural benchmark model; arg 1: the shipped default model (real skin weights).
BENCHMARK(BM_PoseOnly)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseOnlyLevel)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseOnlySkeleton)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShapeAndPose)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShapeAndPoseLevel)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Normals)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Batch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
