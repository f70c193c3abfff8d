#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "paths.hpp"

// The tests write their files (meshes, scans, models) relative to the working directory: run them
// inside the build tree's scratch folder whatever directory the binary was started from, so a run
// from the checkout never leaves files among the sources.
int main(int argc, char* argv[]) {
    std::error_code error;
    const std::filesystem::path scratch = sscape_paths::scratch_folder();
    std::filesystem::create_directories(scratch, error);
    if (!error) std::filesystem::current_path(scratch, error);
    if (error) {
        std::fprintf(stderr, "sscape_tests: cannot work in %s: %s\n", scratch.string().c_str(),
                     error.message().c_str());
        return 2;
    }
    return Catch::Session().run(argc, argv);
}
