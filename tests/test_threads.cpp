// Many bodies sharing one model on several threads give exactly what one thread gives.
// (Catch2 assertions are not thread-safe: the worker code reports failure as an empty result.)
#include "support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <thread>

namespace {

std::vector<float> synthesize(ssc_model* m, int i) {
    const uint32_t K = ssc_model_shape_count(m), J = ssc_model_joint_count(m);
    auto b = test::body(m);
    std::vector<float> shape(K), pose(3ull * J);
    for (uint32_t k = 0; k < K; ++k) shape[k] = float(std::sin(i * 3.1 + k));
    for (uint32_t j = 0; j < 3 * J; ++j) pose[j] = float(0.4 * std::cos(i * 1.3 + j));
    if (!b || ssc_body_set_shape(b.get(), shape.data(), K) != SSC_OK ||
        ssc_body_set_pose_axis_angle(b.get(), pose.data(), J, nullptr) != SSC_OK)
        return {};
    auto v = test::posed(m, b.get());
    std::vector<float> n(v.size());
    if (ssc_body_get_normals(b.get(), n.data(), ssc_model_vertex_count(m), 0) != SSC_OK) return {};
    v.insert(v.end(), n.begin(), n.end());
    return v;
}

}  // namespace

TEST_CASE("bodies on several threads match one thread exactly", "[threads]") {
    auto model = test::load(ssc::format::write_model(test::mini_model(true).data));
    REQUIRE(model);
    const int bodies = 32, threads = 4;
    std::vector<std::vector<float>> reference(bodies), parallel(bodies);
    for (int i = 0; i < bodies; ++i) reference[i] = synthesize(model.get(), i);
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (int i = t; i < bodies; i += threads) parallel[i] = synthesize(model.get(), i);
        });
    for (auto& th : pool) th.join();
    for (int i = 0; i < bodies; ++i) {
        REQUIRE(!reference[i].empty());
        REQUIRE(parallel[i] == reference[i]);
    }
}
