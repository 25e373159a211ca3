// Outputs are whole or absent: a crash, a full disk or an exception half-way through leaves
// at most a hidden temporary file behind a failure we report, never a truncated output.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>

#include "rtt/error.h"
#include "rtt/io.h"

namespace rtt {
namespace {

/// The temporary file: removed on destruction unless committed.
class TempFile {
public:
    explicit TempFile(const std::string& path) : target_(path) {
        const size_t slash = path.find_last_of('/');
        const std::string dir =
            slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
        const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
        if (base.empty()) throw Error(path + ": not a file name");
        // A folder in the way: rename() would refuse it too, but with "Device or resource
        // busy" for "." and only after the file was written.
        struct stat st;
        if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
            throw Error(path + ": is a directory, not a file");
        name_ = dir + "." + base + ".tmpXXXXXX";
        const int fd = mkstemp(name_.data());
        if (fd < 0) throw Error(path + ": cannot create file: " + std::strerror(errno));
        // mkstemp creates mode 0600; outputs are ordinary files.
        fchmod(fd, 0644);
        file_ = fdopen(fd, "wb");
        if (!file_) {
            const int err = errno;
            close(fd);
            unlink(name_.c_str());
            throw Error(path + ": cannot open file: " + std::strerror(err));
        }
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    ~TempFile() {
        if (file_) std::fclose(file_);
        if (!committed_) unlink(name_.c_str());
    }

    std::FILE* file() const { return file_; }

    void commit() {
        bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
        int err = ok ? 0 : errno;
        if (ok && fsync(fileno(file_)) != 0) {
            ok = false;
            err = errno;
        }
        const int closed = std::fclose(file_);
        file_ = nullptr;
        if (ok && closed != 0) {
            ok = false;
            err = errno;
        }
        if (ok && std::rename(name_.c_str(), target_.c_str()) != 0) {
            ok = false;
            err = errno;
        }
        if (!ok) throw Error(target_ + ": cannot write file: " + std::strerror(err));
        committed_ = true;
    }

private:
    std::string target_;
    std::string name_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
};

}  // namespace

void write_file_atomically(const std::string& path, const std::function<void(std::FILE*)>& write) {
    TempFile temp(path);
    write(temp.file());
    temp.commit();
}

}  // namespace rtt
