#include "common/output_paths.hpp"

#include <filesystem>
#include <system_error>

namespace ssc {

void refuse_output_over_input(const std::string& output, const std::vector<std::string>& inputs) {
    if (output.empty()) return;
    for (const std::string& input : inputs) {
        if (input.empty()) continue;
        std::error_code error;  // equivalent() reports an error when neither exists: not the same file
        if (std::filesystem::equivalent(output, input, error) && !error)
            throw Error(SSC_ERROR_INVALID_ARGUMENT, "the output " + output + " is the input " + input +
                                                        (output == input ? "" : " (the same file)") + "; write it elsewhere: an input is never replaced");
    }
}

}  // namespace ssc
