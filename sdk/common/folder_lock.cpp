#include "common/folder_lock.hpp"

#include "common/error.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

namespace ssc {

FolderLock::FolderLock(const std::string& folder, const std::string& what) : folder_(folder) {
    std::error_code error;
    created_ = !std::filesystem::exists(folder, error);
    std::filesystem::create_directories(folder, error);
    if (!std::filesystem::is_directory(folder))
        fail(SSC_ERROR_IO, "cannot create the output folder " + folder + (error ? ": " + error.message() : ": a file of that name is in the way"));
    path_ = (std::filesystem::path(folder) / ".sscape-lock").string();
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(SSC_ERROR_IO, "cannot lock the output folder " + folder + ": " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const int why = errno;
        char holder[32] = {};
        const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
        ::close(fd_);
        fd_ = -1;
        if (why != EWOULDBLOCK) fail(SSC_ERROR_IO, "cannot lock the output folder " + folder + ": " + std::strerror(why));
        fail(SSC_ERROR_IO, "the output folder " + folder + " is in use by another " + what +
                               (n > 0 ? " (process " + std::string(holder, std::size_t(n)) + ")" : std::string()) +
                               ": wait for it to end, or give another folder");
    }
    // The holder's process id, for the message another run gets.
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
        // The id is only for messages: a lock without it still locks.
    }
}

FolderLock::~FolderLock() {
    if (fd_ < 0) return;
    if (created_) {  // still holding the lock: nobody else is in the folder
        std::error_code error;
        bool only_the_lock = true;
        for (const auto& entry : std::filesystem::directory_iterator(folder_, error))
            only_the_lock &= entry.path().filename() == ".sscape-lock";
        if (!error && only_the_lock) {
            ::unlink(path_.c_str());
            std::filesystem::remove(folder_, error);
        }
    }
    ::close(fd_);  // drops the lock
}

}  // namespace ssc
