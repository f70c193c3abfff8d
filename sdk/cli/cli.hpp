// The `sscape` command line: one file per command, built on the public C API except where a
// command needs the C++ tools (make-test-model and train write models; simulate and the fit
// picture use the simulator and renderer). Options are parsed by CLI11: each command file declares
// its options with their help text, and checks what CLI11 cannot (combinations, model-dependent
// names) in its run function.
#pragma once

#include <sscape/sscape.h>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ssc::training {
struct SegmentCompactness;
}

namespace ssc::cli {

// A usage or input problem found after parsing: printed with a pointer to the command's --help,
// exit code 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Runs a parsed command; returns the process exit code.
using Run = std::function<int()>;

// Each command adds itself to the app (its options, their help) and returns how to run it once the
// command line is parsed.
Run add_info(CLI::App& app);
Run add_synth(CLI::App& app);
Run add_make_test_model(CLI::App& app);
Run add_train(CLI::App& app);
Run add_learn(CLI::App& app);      // with training (SSCAPE_BUILD_TRAINING)
Run add_bootstrap(CLI::App& app);  // with training
Run add_evaluate(CLI::App& app);   // with training
Run add_fit(CLI::App& app);
Run add_simulate(CLI::App& app);
Run add_measure(CLI::App& app);
Run add_register(CLI::App& app);

// The optional MODEL positional every model-reading command takes.
void add_model_argument(CLI::App& command, std::string& path);

// Validators: a finite number in [lo, hi] (CLI::Range lets NaN through), and a file name ending in
// one of the given extensions.
CLI::Validator finite_in(double lo, double hi);
CLI::Validator extension(const std::string& ext);

// The posture normalizations learn, bootstrap and evaluate accept (learning::posture_from_name's).
// Each segment's own components beside the whole body's, as shares of the segment's variance
// (learn's and train's report); nothing for none.
void print_segment_compactness(const std::vector<training::SegmentCompactness>& segments);

inline const std::vector<std::string> kPostureNames = {"none", "skeleton", "laplacian"};

// The help layout: CLI11's, with long descriptions wrapped to 100 columns.
std::shared_ptr<CLI::Formatter> help_formatter();

// Throws std::runtime_error with the library's message when status is not SSC_OK.
void check(ssc_status status, const std::string& what);

// Parses "1.5,-2,0" into finite floats; UsageError naming option on anything else.
std::vector<float> parse_floats(const std::string& text, const std::string& option);

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

// A context whose log prints the library's warnings and errors on stderr (the caller destroys it).
ssc_context* new_context();

// Creates the folder an output file goes into (and its parents) when it is missing, as users expect
// of `-o new/folder/body.obj`; a std::runtime_error naming the folder when it cannot be made.
void create_parent_folder(const std::string& path);

// path with suffix inserted before its extension: ("out/fit.obj", "_frame1") -> "out/fit_frame1.obj".
std::string with_suffix(const std::string& path, const std::string& suffix);

}  // namespace ssc::cli
