// Shared helpers for the tests: small models built in code, loading through the C API.
#pragma once

#include "paths.hpp"

#include "capi/cpp_access.hpp"
#include "sscape_format/model_io.hpp"
#include "testing/synthetic_model.hpp"

#include <sscape/sscape.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace test {

// Whether this build runs under AddressSanitizer (SSCAPE_SANITIZE): there the end-to-end tests run
// their steps on less data, since their figures are checked by the Release run and the sanitizers
// look for memory errors, which the same code on fewer scans shows as well.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool sanitized = true;
#else
inline constexpr bool sanitized = false;
#endif

// The MakeHuman assets' folder as CTest passes it (SSCAPE_MAKEHUMAN), or "" when it is not there:
// tests that need it skip with a visible "SKIPPED:" message.
inline std::string makehuman_root() {
    const char* env = std::getenv("SSCAPE_MAKEHUMAN");
    return env && std::filesystem::is_directory(std::string(env) + "/makehuman") ? env : "";
}

// A fresh, empty folder AREA/NAME under the test's working directory.
inline std::string fresh_folder(const std::string& area, const std::string& name) {
    const std::filesystem::path p = std::filesystem::current_path() / area / name;
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p.string();
}

// The shipped default model's file (tests/paths.hpp).
inline std::string default_model_file() { return sscape_paths::default_model_file(); }

// A small model: 6 joints, 300 vertices, 4 components; identity rest orientations unless asked.
inline ssc::testing::SyntheticModel mini_model(bool aligned = false, uint32_t seed = 7) {
    ssc::testing::SyntheticSpec spec;
    spec.skeleton = ssc::testing::SyntheticSkeleton::Mini6;
    spec.vertex_count = 300;
    spec.components = 4;
    spec.seed = seed;
    spec.aligned_rest_orientations = aligned;
    return ssc::testing::build_synthetic_model(spec);
}

inline std::vector<unsigned char> mini_bytes(bool aligned = false) { return ssc::format::write_model(mini_model(aligned).data); }

struct ModelDeleter {
    void operator()(ssc_model* m) const { ssc_model_release(m); }
};
struct BodyDeleter {
    void operator()(ssc_body* b) const { ssc_body_destroy(b); }
};
using ModelPtr = std::unique_ptr<ssc_model, ModelDeleter>;
using BodyPtr = std::unique_ptr<ssc_body, BodyDeleter>;

inline ModelPtr load(const std::vector<unsigned char>& bytes, ssc_context* ctx = nullptr) {
    ssc_model* m = nullptr;
    if (ssc_model_load_memory(ctx, bytes.data(), bytes.size(), &m) != SSC_OK) return nullptr;
    return ModelPtr(m);
}

inline ModelPtr default_model() {
    ssc_model* m = nullptr;
    if (ssc_model_load_default(nullptr, &m) != SSC_OK) return nullptr;
    return ModelPtr(m);
}

// The default model as the C++ library sees it, loaded once for the test run.
inline const ssc::Model& default_cpp_model() {
    static const ModelPtr handle = default_model();
    return ssc::model_of(handle.get());
}

inline BodyPtr body(ssc_model* m) {
    ssc_body* b = nullptr;
    if (ssc_body_create(m, nullptr, &b) != SSC_OK) return nullptr;
    return BodyPtr(b);
}

// The default model and one body of it, released at scope end; throws (a test failure) when they
// cannot be made.
struct DefaultBody {
    ModelPtr owned_model = default_model();
    BodyPtr owned_body = owned_model ? test::body(owned_model.get()) : nullptr;
    ssc_model* model = owned_model.get();
    ssc_body* body = owned_body.get();
    DefaultBody() {
        if (!body) throw std::runtime_error(std::string("cannot make a body of the default model: ") + ssc_last_error());
    }
};

// Posed (or rest) vertices of a body of model m, packed xyz.
inline std::vector<float> posed(ssc_model* m, ssc_body* b) {
    std::vector<float> v(3ull * ssc_model_vertex_count(m));
    if (ssc_body_get_vertices(b, v.data(), ssc_model_vertex_count(m), 0) != SSC_OK) v.clear();
    return v;
}
inline std::vector<float> rest(ssc_model* m, ssc_body* b) {
    std::vector<float> v(3ull * ssc_model_vertex_count(m));
    if (ssc_body_get_rest_vertices(b, v.data(), ssc_model_vertex_count(m), 0) != SSC_OK) v.clear();
    return v;
}

}  // namespace test
