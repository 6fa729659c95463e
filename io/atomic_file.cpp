#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace atelier::io {

namespace {

Error systemError(const std::filesystem::path& path, const std::string& what) {
    return Error{path.string(), "", what + ": " + std::strerror(errno)};
}

/// Closes a descriptor and removes the temporary file unless released.
class TempFile {
  public:
    TempFile(int fd, std::string path) : m_fd(fd), m_path(std::move(path)) {}
    ~TempFile() {
        if (m_fd >= 0) {
            ::close(m_fd);
        }
        if (!m_path.empty()) {
            ::unlink(m_path.c_str());
        }
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    int fd() const { return m_fd; }
    const std::string& path() const { return m_path; }
    /// Closes the descriptor; returns false (errno set) when close reports an error.
    bool close() {
        const int fd = m_fd;
        m_fd = -1;
        return ::close(fd) == 0;
    }
    /// The file was renamed into place: do not remove it.
    void release() { m_path.clear(); }

  private:
    int m_fd;
    std::string m_path;
};

/// Why a file that is not a regular file is refused, naming its kind.
std::string notRegularFile(mode_t mode) {
    if (S_ISDIR(mode)) {
        return "not a regular file (a directory)";
    }
    if (S_ISFIFO(mode)) {
        return "not a regular file (a FIFO)";
    }
    if (S_ISCHR(mode)) {
        return "not a regular file (a character device)";
    }
    if (S_ISBLK(mode)) {
        return "not a regular file (a block device)";
    }
    if (S_ISSOCK(mode)) {
        return "not a regular file (a socket)";
    }
    return "not a regular file";
}

Error tooLarge(const std::filesystem::path& path, std::uint64_t size, std::uint64_t maxBytes) {
    return Error{path.string(), "",
                 "file too large: " + std::to_string(size) + " bytes (the limit is " +
                     std::to_string(maxBytes) + " bytes)"};
}

/// Removes `.NAME.tmp-PID-*` files in `dir` left by processes that no longer run (a write
/// killed before its rename). Files of running processes, this one included, are kept.
void removeStaleTempFiles(const std::filesystem::path& dir, const std::string& prefix) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) {
            continue;
        }
        const std::size_t dash = name.find('-', prefix.size());
        if (dash == std::string::npos || dash == prefix.size() || dash - prefix.size() > 9) {
            continue;
        }
        pid_t pid = 0;
        bool digits = true;
        for (std::size_t k = prefix.size(); k < dash; ++k) {
            digits = digits && name[k] >= '0' && name[k] <= '9';
            pid = digits ? pid * 10 + (name[k] - '0') : pid;
        }
        if (digits && pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) {
            std::filesystem::remove(entry.path(), ec);
        }
    }
}

} // namespace

Result<void> writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
    if (path.empty() || !path.has_filename()) {
        return Error{path.string(), "", "not a file path"};
    }
    const std::filesystem::path dir = path.parent_path().empty() ? "." : path.parent_path();
    std::string prefix = path.filename().string();
    prefix.insert(prefix.begin(), '.');
    prefix.append(".tmp-");
    removeStaleTempFiles(dir, prefix);
    std::string tmpl = (dir / (prefix + std::to_string(::getpid()) + "-XXXXXX")).string();
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) {
        return systemError(path, "cannot create a temporary file in " + dir.string());
    }
    TempFile tmp(fd, tmpl);
    // mkstemp creates the file 0600; a written file should have the usual permissions.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(tmp.fd(), 0666 & ~mask);

    const char* data = contents.data();
    std::size_t left = contents.size();
    while (left > 0) {
        const ssize_t n = ::write(tmp.fd(), data, left);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return systemError(path, "cannot write");
        }
        data += n;
        left -= static_cast<std::size_t>(n);
    }
    if (::fsync(tmp.fd()) != 0) {
        return systemError(path, "cannot flush to disk");
    }
    if (!tmp.close()) {
        return systemError(path, "cannot close");
    }
    if (::rename(tmp.path().c_str(), path.c_str()) != 0) {
        return systemError(path, "cannot rename the temporary file into place");
    }
    tmp.release();
    // Make the rename itself durable (best effort: some file systems refuse fsync on dirs).
    const int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
    return {};
}

Result<std::string> readFile(const std::filesystem::path& path, std::uint64_t maxBytes) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked on the open
    // descriptor, so the file cannot be swapped between the check and the read.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        return systemError(path, "cannot open");
    }
    TempFile file(fd, ""); // closes the descriptor; no path, nothing to remove
    struct stat info {};
    if (::fstat(file.fd(), &info) != 0) {
        return systemError(path, "cannot read");
    }
    if (!S_ISREG(info.st_mode)) {
        return Error{path.string(), "", notRegularFile(info.st_mode)};
    }
    const auto size = static_cast<std::uint64_t>(info.st_size);
    if (size > maxBytes) {
        return tooLarge(path, size, maxBytes);
    }
    std::string out(static_cast<std::size_t>(size), '\0');
    std::size_t done = 0;
    for (;;) {
        if (done == out.size()) {
            // The file may have grown since fstat: read on, within the limit.
            if (done >= maxBytes) {
                char probe = 0;
                const ssize_t n = ::read(file.fd(), &probe, 1);
                if (n > 0) {
                    return tooLarge(path, done + 1, maxBytes);
                }
                break;
            }
            out.resize(done + std::min<std::uint64_t>(maxBytes - done, 64 * 1024));
        }
        const ssize_t n = ::read(file.fd(), out.data() + done, out.size() - done);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return systemError(path, "cannot read");
        }
        if (n == 0) {
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    out.resize(done);
    return out;
}

} // namespace atelier::io
