#include "scene/assimp_sandbox.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <optional>
#include <type_traits>

#include "rtt/error.h"
#include "rtt/memory_budget.h"
#include "scene/importers.h"

namespace rtt::detail {
namespace {

// Every field of Scene crosses the pipe. A new field must be added to serialize_scene and
// deserialize_scene: these sizes make the build fail until someone looks here.
static_assert(sizeof(Scene) == 296 && sizeof(Material) == 64 && sizeof(Light) == 52 &&
                  sizeof(Camera) == 40,
              "Scene changed: update serialize_scene / deserialize_scene (assimp_sandbox.cpp)");
static_assert(std::is_trivially_copyable_v<Light> && std::is_trivially_copyable_v<Camera> &&
              std::is_trivially_copyable_v<Vec3f> && std::is_trivially_copyable_v<TriangleIndices>);

constexpr uint32_t magic = 0x52545453;  // "STTR"
enum class Reply : uint8_t { scene = 1, error = 2 };

/// Sends bytes to a string or, buffered, to a file descriptor (the pipe), so a big scene is
/// never held twice in the child.
class Writer {
public:
    explicit Writer(std::string& out) : out_(&out) {}
    explicit Writer(int fd) : fd_(fd) {}
    ~Writer() { flush(); }
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    template <typename T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        raw(&v, sizeof v);
    }
    void string(const std::string& s) {
        pod(uint64_t(s.size()));
        raw(s.data(), s.size());
    }
    template <typename T>
    void vector(const std::vector<T>& v) {
        pod(uint64_t(v.size()));
        raw(v.data(), v.size() * sizeof(T));
    }
    /// False once a write to the descriptor failed.
    bool flush() {
        if (fd_ >= 0 && !write_all(buffer_.data(), buffer_.size())) ok_ = false;
        buffer_.clear();
        return ok_;
    }

private:
    void raw(const void* p, size_t n) {
        if (n == 0) return;
        if (out_) {
            out_->append(static_cast<const char*>(p), n);
            return;
        }
        if (buffer_.size() + n > buffer_bytes) flush();
        if (n >= buffer_bytes) {
            if (!write_all(static_cast<const char*>(p), n)) ok_ = false;
        } else {
            buffer_.append(static_cast<const char*>(p), n);
        }
    }
    bool write_all(const char* p, size_t n) const {
        for (size_t done = 0; done < n;) {
            const ssize_t k = ::write(fd_, p + done, n - done);
            if (k < 0 && errno == EINTR) continue;
            if (k <= 0) return false;
            done += size_t(k);
        }
        return true;
    }
    static constexpr size_t buffer_bytes = size_t(1) << 16;
    std::string* out_ = nullptr;
    int fd_ = -1;
    std::string buffer_;
    bool ok_ = true;
};

/// Reads what Writer wrote, from a string or a descriptor; throws rtt::Error if it ends early.
class Reader {
public:
    explicit Reader(const std::string& bytes) : bytes_(&bytes) {}
    explicit Reader(int fd) : fd_(fd) {}

    template <typename T>
    T pod() {
        T v;
        raw(&v, sizeof v);
        return v;
    }
    std::string string() {
        std::string s;
        read_chunked(s, pod<uint64_t>());
        return s;
    }
    template <typename T>
    std::vector<T> vector() {
        std::vector<T> v;
        read_chunked(v, pod<uint64_t>());
        return v;
    }
    /// True when nothing is left.
    bool at_end() {
        if (bytes_) return at_ == bytes_->size();
        return !fill();
    }

private:
    [[noreturn]] static void fail() { throw Error("assimp sandbox: malformed or truncated reply"); }

    /// Grows `out` as data arrives (a count from a truncated reply never allocates ahead).
    template <typename Container>
    void read_chunked(Container& out, uint64_t count) {
        constexpr uint64_t chunk = uint64_t(1) << 20;
        for (uint64_t done = 0; done < count;) {
            const uint64_t n = std::min(chunk, count - done);
            out.resize(size_t(done + n));
            raw(out.data() + done, size_t(n) * sizeof(typename Container::value_type));
            done += n;
        }
    }
    void raw(void* p, size_t n) {
        auto* dst = static_cast<char*>(p);
        while (n > 0) {
            if (bytes_) {
                if (n > bytes_->size() - at_) fail();
                std::memcpy(dst, bytes_->data() + at_, n);
                at_ += n;
                return;
            }
            if (at_ == buffer_.size() && !fill()) fail();
            const size_t k = std::min(n, buffer_.size() - at_);
            std::memcpy(dst, buffer_.data() + at_, k);
            at_ += k;
            dst += k;
            n -= k;
        }
    }
    /// Refills the buffer from the descriptor; false at the end of the stream.
    bool fill() {
        if (at_ < buffer_.size()) return true;
        buffer_.resize(size_t(1) << 16);
        for (;;) {
            const ssize_t k = ::read(fd_, buffer_.data(), buffer_.size());
            if (k < 0 && errno == EINTR) continue;
            buffer_.resize(k > 0 ? size_t(k) : 0);
            at_ = 0;
            return k > 0;
        }
    }
    const std::string* bytes_ = nullptr;
    int fd_ = -1;
    std::string buffer_;
    size_t at_ = 0;
};

void write_scene(Writer& w, const Scene& s) {
    w.string(s.name);
    w.vector(s.vertices);
    w.vector(s.triangles);
    w.vector(s.triangle_material);
    w.vector(s.normals);
    w.pod(uint64_t(s.materials.size()));
    for (const Material& m : s.materials) {
        w.string(m.name);
        w.pod(m.diffuse);
        w.pod(m.specular);
        w.pod(m.shininess);
        w.pod(m.mirror);
    }
    w.vector(s.lights);
    w.pod(uint8_t(s.camera.has_value()));
    if (s.camera) w.pod(*s.camera);
    w.pod(uint64_t(s.file_cameras.size()));
    for (const FileCamera& c : s.file_cameras) {
        w.string(c.name);
        w.pod(c.camera);
    }
    w.pod(s.background);
    w.pod(uint64_t(s.warnings.size()));
    for (const std::string& warning : s.warnings) w.string(warning);
    w.pod(uint64_t(s.warning_count));
}

Scene read_scene(Reader& r) {
    Scene s;
    s.name = r.string();
    s.vertices = r.vector<Vec3f>();
    s.triangles = r.vector<TriangleIndices>();
    s.triangle_material = r.vector<uint32_t>();
    s.normals = r.vector<Vec3f>();
    const auto materials = r.pod<uint64_t>();
    for (uint64_t i = 0; i < materials; ++i) {
        Material m;
        m.name = r.string();
        m.diffuse = r.pod<Vec3f>();
        m.specular = r.pod<Vec3f>();
        m.shininess = r.pod<float>();
        m.mirror = r.pod<float>();
        s.materials.push_back(std::move(m));
    }
    s.lights = r.vector<Light>();
    if (r.pod<uint8_t>()) s.camera = r.pod<Camera>();
    const auto cameras = r.pod<uint64_t>();
    for (uint64_t i = 0; i < cameras; ++i) {
        FileCamera c;
        c.name = r.string();
        c.camera = r.pod<Camera>();
        s.file_cameras.push_back(std::move(c));
    }
    s.background = r.pod<Vec3f>();
    const auto warnings = r.pod<uint64_t>();
    for (uint64_t i = 0; i < warnings; ++i) {
        std::string warning = r.string();
        if (i < Scene::max_kept_warnings) s.warnings.push_back(std::move(warning));
    }
    s.warning_count = size_t(r.pod<uint64_t>());
    return s;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool under_asan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool under_asan = true;
#else
constexpr bool under_asan = false;
#endif
#else
constexpr bool under_asan = false;
#endif

/// This process's data segment (VmData: heap and private writable mappings), in bytes.
uint64_t data_bytes() {
    std::ifstream in("/proc/self/status");
    std::string key;
    uint64_t kib = 0;
    while (in >> key)
        if (key == "VmData:" && in >> kib) return kib * 1024;
    return 0;
}

/// Bounds the child: on some malformed files assimp allocates without end (a 3 KB COLLADA
/// with an index out of range grew to gigabytes over minutes), so its data may grow by
/// max(1 GiB, 256 x the file's size), within the memory budget; an allocation past that
/// fails and the import ends in an error. Not under AddressSanitizer, whose shadow memory
/// counts as data. RTT_IMPORT_CPU_SECONDS (scripts/fuzz.sh) also caps its CPU time.
void limit_child(const std::string& path) {
    if (!under_asan) {
        std::error_code ec;
        const uint64_t size = std::filesystem::file_size(path, ec);
        const uint64_t grow =
            std::min(memory_budget(), std::max(uint64_t(1) << 30, (ec ? 0 : size) * 256));
        const uint64_t cap = data_bytes() + grow;
        const rlimit data{rlim_t(cap), rlim_t(cap)};
        setrlimit(RLIMIT_DATA, &data);
    }
    if (const char* s = std::getenv("RTT_IMPORT_CPU_SECONDS")) {
        const long seconds = std::strtol(s, nullptr, 10);
        if (seconds > 0) {
            const rlimit cpu{rlim_t(seconds), rlim_t(seconds)};
            setrlimit(RLIMIT_CPU, &cpu);
        }
    }
}

/// The child: import, then reply (nothing is sent before the import finished), and leave
/// without running the parent's atexit handlers or destructors (they belong to the parent). A
/// crash lands in the default handler: the parent sees the signal, nobody prints a report.
[[noreturn]] void run_child(const std::string& path, int fd) {
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGXCPU}) std::signal(sig, SIG_DFL);
    limit_child(path);
    // Some of assimp's parsers print to stdout or stderr themselves (OpenGEX's: "nullptr
    // returned by creating DDLNode."), past its logger: the child's output goes nowhere, so
    // that a refusal stays one line.
    if (const int null = open("/dev/null", O_WRONLY); null >= 0) {
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
        close(null);
    }
    std::string error;
    try {
        const Scene scene = import_assimp(path);
        Writer w(fd);
        w.pod(magic);
        w.pod(Reply::scene);
        write_scene(w, scene);
        _exit(w.flush() ? 0 : 3);
    } catch (const std::bad_alloc&) {
        error = path + ": out of memory while importing";
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = path + ": the importer (assimp) failed on this file";
    }
    Writer w(fd);
    w.pod(magic);
    w.pod(Reply::error);
    w.string(error);
    _exit(w.flush() ? 0 : 3);
}

/// Waits for the child; throws rtt::Error naming `path` unless it exited with status 0.
void reap(pid_t pid, const std::string& path) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status))
        throw Error(path, 0,
                    "the importer (assimp) crashed on this file (signal " +
                        std::to_string(WTERMSIG(status)) +
                        "); the file is malformed or not supported");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error(path, 0,
                    "the importer (assimp) failed on this file (exit status " +
                        std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
}

}  // namespace

std::string serialize_scene(const Scene& scene) {
    std::string bytes;
    {
        Writer w(bytes);
        write_scene(w, scene);
    }
    return bytes;
}

Scene deserialize_scene(const std::string& bytes) {
    Reader r(bytes);
    Scene s = read_scene(r);
    if (!r.at_end()) throw Error("assimp sandbox: malformed reply");
    return s;
}

Scene import_assimp_isolated(const std::string& path) {
    int fds[2];
    if (pipe(fds) != 0)
        throw Error(path, 0, std::string("cannot create a pipe: ") + std::strerror(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        const int err = errno;
        close(fds[0]);
        close(fds[1]);
        throw Error(path, 0,
                    std::string("cannot start the importer process: ") + std::strerror(err));
    }
    if (pid == 0) {
        close(fds[0]);
        run_child(path, fds[1]);
    }
    close(fds[1]);
    // The scene is read while the child writes it. If the reply breaks off, the child's exit
    // status says why.
    Reader r(fds[0]);
    Scene scene;
    std::optional<std::string> error;
    bool complete = false;
    try {
        if (r.pod<uint32_t>() != magic) throw Error("assimp sandbox: no reply");
        if (r.pod<Reply>() == Reply::error)
            error = r.string();
        else
            scene = read_scene(r);
        complete = r.at_end();
    } catch (const Error&) {
        complete = false;
    }
    close(fds[0]);
    reap(pid, path);
    if (!complete) throw Error(path, 0, "the importer (assimp) gave a truncated answer");
    if (error) throw Error(*error);
    return scene;
}

}  // namespace rtt::detail
