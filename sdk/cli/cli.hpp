// The `sscape` command line: one file per command, built on the public C API except where a
// command needs the C++ tools (make-test-model and train write models; simulate and the fit
// picture use the simulator and renderer).
#pragma once

#include <sscape/sscape.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ssc::cli {

// A usage or input problem: printed with the command's usage, exit code 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws std::runtime_error with the library's message when status is not SSC_OK.
void check(ssc_status status, const std::string& what);

// Parses "1.5,-2,0" into floats; UsageError on anything else.
std::vector<float> parse_floats(const std::string& text, const std::string& option);
uint32_t parse_count(const std::string& text, const std::string& option);

// The value after option args[i] (advancing i); UsageError when there is none.
const std::string& option_value(const std::vector<std::string>& args, std::size_t& i);

// The handles a command creates, released however it leaves (a body or fitter holds its own model
// reference, so the order does not matter; every release accepts NULL).
struct Handles {
    ssc_model* model = nullptr;
    ssc_body* body = nullptr;
    ssc_fitter* fitter = nullptr;
    explicit Handles(ssc_model* m) : model(m) {}
    ~Handles() {
        ssc_fitter_destroy(fitter);
        ssc_body_destroy(body);
        ssc_model_release(model);
    }
    Handles(const Handles&) = delete;
    Handles& operator=(const Handles&) = delete;
};

// Loads MODEL, or the default model compiled into the library when path is empty.
ssc_model* load_model(const std::string& path);

// path with suffix inserted before its extension: ("out/fit.obj", "_frame1") -> "out/fit_frame1.obj".
std::string with_suffix(const std::string& path, const std::string& suffix);

int cmd_info(const std::vector<std::string>& args);
int cmd_synth(const std::vector<std::string>& args);
int cmd_make_test_model(const std::vector<std::string>& args);
int cmd_train(const std::vector<std::string>& args);
int cmd_fit(const std::vector<std::string>& args);
int cmd_simulate(const std::vector<std::string>& args);
int cmd_measure(const std::vector<std::string>& args);

}  // namespace ssc::cli
