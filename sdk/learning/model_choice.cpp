#include "learning/model_choice.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "learning/posture_fit.hpp"
#include "sscape_format/model_io.hpp"

namespace ssc::learning {

namespace {

std::vector<unsigned char> read_model_bytes(const std::string& path) {
    const std::string s = read_regular_file(path, 1ull << 30);
    return std::vector<unsigned char>(s.begin(), s.end());
}

}  // namespace

std::vector<unsigned char> starting_model_file(const std::optional<std::string>& path, bool template_only_model,
                                               const std::vector<unsigned char>& builtin) {
    std::vector<unsigned char> bytes = path ? read_model_bytes(*path) : builtin;
    if (template_only_model) bytes = format::write_model(template_only(format::read_model(bytes.data(), bytes.size())));
    else format::read_model(bytes.data(), bytes.size());  // refuses a bad model now
    return bytes;
}

std::vector<unsigned char> posture_model_file(Posture posture, const std::optional<std::string>& path,
                                              const std::vector<unsigned char>& start, const std::vector<unsigned char>& builtin) {
    if (posture != Posture::Skeleton || (path && path->empty())) return {};
    const format::ModelData start_data = format::read_model(start.data(), start.size());
    if (path) {
        std::vector<unsigned char> bytes = read_model_bytes(*path);
        format::ModelData model;
        try {
            model = format::read_model(bytes.data(), bytes.size());
        } catch (const Error& e) {
            throw Error(SSC_ERROR_INVALID_ARGUMENT, "the posture model " + *path + ": " + e.what());
        }
        check_posture_model(start_data, model);
        return bytes;
    }
    try {
        check_posture_model(start_data, format::read_model(builtin.data(), builtin.size()));
    } catch (const Error&) {
        return {};  // a starting model of another template: its rounds' own fits
    }
    return builtin;
}

}  // namespace ssc::learning
