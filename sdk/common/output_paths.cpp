#include "common/output_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace ssc {

OutputFiles::OutputFiles(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
        if (path.empty()) continue;
        const std::filesystem::path parent = std::filesystem::path(path).parent_path();
        std::string probe = ((parent.empty() ? std::filesystem::path(".") : parent) / ".sscape-probe-XXXXXX").string();
        const int fd = ::mkstemp(probe.data());
        if (fd < 0) fail(SSC_ERROR_IO, "cannot write '" + path + "': " + std::strerror(errno));
        ::close(fd);
        ::unlink(probe.c_str());
        Before b;
        b.path = path;
        struct stat st {};
        if (::stat(path.c_str(), &st) == 0) b.existed = true, b.device = st.st_dev, b.inode = st.st_ino;
        files_.push_back(b);
    }
}

OutputFiles::~OutputFiles() {
    if (kept_) return;
    for (const Before& b : files_) {
        struct stat st {};
        if (::stat(b.path.c_str(), &st) != 0) continue;
        if (!b.existed || st.st_dev != b.device || st.st_ino != b.inode) ::unlink(b.path.c_str());
    }
}

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
