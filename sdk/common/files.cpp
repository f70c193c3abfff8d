#include "common/files.hpp"

#define XXH_INLINE_ALL  // header-only use of Debian's xxhash
#include <xxhash.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ssc {
namespace {

std::string why() { return std::strerror(errno); }

// Closes a descriptor at scope end.
struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

bool write_all(int fd, const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= std::size_t(n);
    }
    return true;
}

// "dir/.name.sscape-tmp-<16 hex digits>" beside the target: hidden, and recognisably ours.
std::string temporary_name(const std::string& path) {
    const std::size_t slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    std::random_device random;
    const uint64_t r = (uint64_t(random()) << 32) ^ random();
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(r));
    return dir + "." + name + ".sscape-tmp-" + hex;
}

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.rfind('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

// Gives the complete unnamed file `fd` a unique temporary name; false when this system cannot.
bool link_unnamed(int fd, std::string& tmp, const std::string& path) {
    char proc[64];
    std::snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
    for (int attempt = 0; attempt < 16; ++attempt) {
        tmp = temporary_name(path);
        if (::linkat(AT_FDCWD, proc, AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) == 0) return true;
        if (errno != EEXIST) return false;
    }
    return false;
}

// The fallback: a new, uniquely named file that must not exist yet and is never a followed link.
int create_named(const std::string& path, std::string& tmp) {
    for (int attempt = 0; attempt < 16; ++attempt) {
        tmp = temporary_name(path);
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) return fd;
    }
    return -1;
}

bool write_synced(int fd, const void* data, std::size_t size) { return write_all(fd, data, size) && ::fsync(fd) == 0; }

// Writes the bytes to a complete, synced file beside `path`, named `tmp` on success. First an
// unnamed O_TMPFILE that is linked to its name only once complete; where the file system has no
// O_TMPFILE (or /proc is missing, which the link needs), a named O_EXCL temporary. On failure
// nothing is left behind and `error` says why.
bool write_temporary(const std::string& path, const void* data, std::size_t size, std::string& tmp, std::string& error) {
    {
        Fd unnamed;
        unnamed.fd = ::open(folder_of(path).c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
        if (unnamed.fd >= 0) {
            if (!write_synced(unnamed.fd, data, size)) return error = why(), false;
            if (link_unnamed(unnamed.fd, tmp, path)) return true;
        }
    }
    Fd named;
    named.fd = create_named(path, tmp);
    if (named.fd < 0) return error = why(), false;
    bool ok = write_synced(named.fd, data, size);
    if (!ok) error = why();
    const int fd = named.fd;
    named.fd = -1;
    if (::close(fd) != 0 && ok) ok = false, error = why();
    if (!ok) ::unlink(tmp.c_str());
    return ok;
}

}  // namespace

std::string read_regular_file(const std::string& path, uint64_t max_bytes, ssc_status too_large) {
    Fd f;
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
    f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (f.fd < 0) fail(SSC_ERROR_IO, "cannot open '" + path + "': " + why());
    struct stat st {};
    if (::fstat(f.fd, &st) != 0) fail(SSC_ERROR_IO, "cannot read '" + path + "': " + why());
    if (S_ISDIR(st.st_mode)) fail(SSC_ERROR_IO, "'" + path + "' is a directory, not a file");
    if (!S_ISREG(st.st_mode)) fail(SSC_ERROR_IO, "'" + path + "' is not a regular file (a FIFO, socket or device)");
    const uint64_t size = uint64_t(st.st_size);
    if (size > max_bytes)
        fail(too_large, "'" + path + "' is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                            " accepted");
    std::string data(std::size_t(size), '\0');
    std::size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::read(f.fd, data.data() + done, data.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) fail(SSC_ERROR_IO, "cannot read '" + path + "': " + why());
        if (n == 0) fail(SSC_ERROR_IO, "'" + path + "' shrank while it was read");
        done += std::size_t(n);
    }
    return data;
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
    SSC_REQUIRE_ARG(!path.empty() && path.back() != '/', "'" + path + "' is not a file name");
    std::string tmp, error;
    if (!write_temporary(path, data, size, tmp, error)) fail(SSC_ERROR_IO, "cannot write '" + path + "': " + error);
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        error = why();
        ::unlink(tmp.c_str());
        fail(SSC_ERROR_IO, "cannot replace '" + path + "': " + error);
    }
}

std::string content_digest(const void* data, std::size_t size) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(XXH3_64bits(data, size)));
    return hex;
}

}  // namespace ssc
