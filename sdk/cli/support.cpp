// Helpers the commands share: model loading, status checks, number lists, validators.
#include "cli.hpp"

#include "training/segment_shapes.hpp"

#include <Eigen/Geometry>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

namespace ssc::cli {

void check(ssc_status status, const std::string& what) {
    if (status != SSC_OK)
        throw std::runtime_error(what + ": " + ssc_status_name(status) + ": " + ssc_last_error());
}

std::vector<float> parse_floats(const std::string& text, const std::string& option) {
    std::vector<float> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        errno = 0;
        const float v = std::strtof(item.c_str(), &end);
        if (item.empty() || *end != '\0' || errno || !std::isfinite(v))
            throw UsageError(option + ": '" + item + "' is not a finite number");
        out.push_back(v);
    }
    if (out.empty()) throw UsageError(option + " needs comma-separated numbers");
    return out;
}

void add_model_argument(CLI::App& command, std::string& path) {
    command.add_option("MODEL", path, "a .sscape model file; without one, the default model built into the library")
        ->type_name("MODEL.sscape");
}

CLI::Validator finite_in(double lo, double hi) {
    std::ostringstream range;
    range << "[" << lo << ", " << hi << "]";
    return CLI::Validator(
        [lo, hi, range = range.str()](std::string& text) -> std::string {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || errno || !std::isfinite(v)) return "'" + text + "' is not a finite number";
            if (v < lo || v > hi) return text + " is outside " + range;
            return {};
        },
        "in " + range.str());
}

CLI::Validator extension(const std::string& ext) {
    return CLI::Validator(
        [ext](std::string& path) -> std::string {
            if (path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0) return {};
            return "'" + path + "' does not end in " + ext;
        },
        "*" + ext);
}

namespace {

// Breaks text into lines of at most width characters at spaces (a longer word stays whole).
std::string wrap(const std::string& text, std::size_t width) {
    std::string out, line, word;
    std::istringstream words(text);
    while (words >> word) {
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            out += line + "\n";
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    return out + line;
}

// CLI11's layout with descriptions wrapped to a terminal's width (CLI11 2.1 does not wrap).
class WrappingFormatter : public CLI::Formatter {
public:
    static constexpr std::size_t kWidth = 100;
    WrappingFormatter() { column_width(32); }
    std::string make_option_desc(const CLI::Option* opt) const override {
        return wrap(CLI::Formatter::make_option_desc(opt), kWidth - get_column_width());
    }
    std::string make_subcommand(const CLI::App* sub) const override {
        std::stringstream out;
        CLI::detail::format_help(out, sub->get_display_name(true), wrap(sub->get_description(), kWidth - get_column_width()),
                                 get_column_width());
        return out.str();
    }
    std::string make_description(const CLI::App* app) const override {
        const std::string text = app->get_description();
        return text.empty() ? std::string() : wrap(text, kWidth) + "\n";
    }
};

}  // namespace

std::shared_ptr<CLI::Formatter> help_formatter() { return std::make_shared<WrappingFormatter>(); }

std::string with_suffix(const std::string& path, const std::string& suffix) {
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos) return path + suffix;
    return path.substr(0, dot) + suffix + path.substr(dot);
}

void create_parent_folder(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code error;
    std::filesystem::create_directories(parent, error);
    if (error || !std::filesystem::is_directory(parent))
        throw std::runtime_error("cannot create the output folder " + parent.string() + (error ? ": " + error.message() : ""));
}

ssc_context* new_context() {
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    // Every warning the library logs (a landmark name it does not know, ...) reaches the user.
    def.log = [](void*, ssc_log_level level, const char* message) {
        std::fprintf(stderr, "%s: %s\n", level >= SSC_LOG_ERROR ? "error" : level == SSC_LOG_WARNING ? "warning" : "note", message);
    };
    def.log_level = SSC_LOG_WARNING;
    ssc_context* context = nullptr;
    check(ssc_context_create(&def, &context), "cannot create the library's context");
    return context;
}

ssc_model* load_model(const std::string& path) {
    std::unique_ptr<ssc_context, void (*)(ssc_context*)> context(new_context(), ssc_context_destroy);  // the model keeps it
    ssc_model* model = nullptr;
    if (path.empty()) check(ssc_model_load_default(context.get(), &model), "cannot load the default model");
    else check(ssc_model_load_file(context.get(), path.c_str(), &model), "cannot load '" + path + "'");
    return model;
}

void print_segment_compactness(const std::vector<training::SegmentCompactness>& segments) {
    if (segments.empty()) return;
    std::printf("segment compactness: share of each segment's variance held by its own first k components / by the whole body's first k\n");
    std::printf("  %-6s %8s %9s", "segment", "vertices", "RMS (mm)");
    const std::size_t K = segments[0].own.size();
    const std::size_t shown[] = {1, 3, 5, 10, 20};
    for (std::size_t k : shown)
        if (k <= K) std::printf("     k=%-3zu", k);
    std::printf("\n");
    for (const auto& s : segments) {
        std::printf("  %-7s %8u %9.1f", s.name.c_str(), s.vertices, std::sqrt(s.variance / std::max(1u, s.vertices)) * 1e3);
        for (std::size_t k : shown)
            if (k <= K) std::printf("  %4.1f/%4.1f", 100 * s.own[k - 1], k <= s.whole_body.size() ? 100 * s.whole_body[k - 1] : NAN);
        std::printf("\n");
    }
}

}  // namespace ssc::cli
