#include "scene/assimp_sandbox.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <exception>
#include <new>
#include <type_traits>

#include "rtt/error.h"
#include "scene/importers.h"

namespace rtt::detail {
namespace {

// Every field of Scene crosses the pipe. A new field must be added to serialize_scene and
// deserialize_scene: these sizes make the build fail until someone looks here.
static_assert(sizeof(Scene) == 232 && sizeof(Material) == 64 && sizeof(Light) == 52 &&
                  sizeof(Camera) == 40,
              "Scene changed: update serialize_scene / deserialize_scene (assimp_sandbox.cpp)");
static_assert(std::is_trivially_copyable_v<Light> && std::is_trivially_copyable_v<Camera> &&
              std::is_trivially_copyable_v<Vec3f> && std::is_trivially_copyable_v<TriangleIndices>);

constexpr uint32_t magic = 0x52545453;  // "STTR"
enum class Reply : uint8_t { scene = 1, error = 2 };

class Writer {
public:
    template <typename T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void string(const std::string& s) {
        pod(uint64_t(s.size()));
        bytes_ += s;
    }
    template <typename T>
    void vector(const std::vector<T>& v) {
        pod(uint64_t(v.size()));
        if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    std::string& bytes() { return bytes_; }

private:
    std::string bytes_;
};

class Reader {
public:
    explicit Reader(const std::string& bytes) : bytes_(bytes) {}
    template <typename T>
    T pod() {
        T v;
        std::memcpy(&v, take(sizeof v), sizeof v);
        return v;
    }
    std::string string() {
        const uint64_t n = pod<uint64_t>();
        return std::string(take(n), size_t(n));
    }
    template <typename T>
    std::vector<T> vector() {
        const uint64_t n = pod<uint64_t>();
        if (n > (bytes_.size() - at_) / sizeof(T)) fail();
        std::vector<T> v(static_cast<size_t>(n));
        if (n > 0) std::memcpy(v.data(), take(n * sizeof(T)), size_t(n) * sizeof(T));
        return v;
    }
    bool done() const { return at_ == bytes_.size(); }

private:
    [[noreturn]] static void fail() { throw Error("assimp sandbox: malformed reply"); }
    const char* take(uint64_t n) {
        if (n > bytes_.size() - at_) fail();
        const char* p = bytes_.data() + at_;
        at_ += size_t(n);
        return p;
    }
    const std::string& bytes_;
    size_t at_ = 0;
};

/// Writes all of `bytes` to `fd` (retrying on EINTR and short writes).
bool write_all(int fd, const std::string& bytes) {
    for (size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += size_t(n);
    }
    return true;
}

/// The child: import, reply, and leave without running the parent's atexit handlers or
/// destructors (they belong to the parent). A crash lands in the default handler: no report.
[[noreturn]] void run_child(const std::string& path, int fd) {
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    Writer w;
    w.pod(magic);
    try {
        const Scene scene = import_assimp(path);
        w.pod(Reply::scene);
        w.bytes() += serialize_scene(scene);
    } catch (const std::bad_alloc&) {
        w.bytes().resize(sizeof magic);
        w.pod(Reply::error);
        w.string(path + ": out of memory while importing");
    } catch (const std::exception& e) {
        w.bytes().resize(sizeof magic);
        w.pod(Reply::error);
        w.string(e.what());
    } catch (...) {
        w.bytes().resize(sizeof magic);
        w.pod(Reply::error);
        w.string(path + ": the importer (assimp) failed on this file");
    }
    _exit(write_all(fd, w.bytes()) ? 0 : 3);
}

}  // namespace

std::string serialize_scene(const Scene& s) {
    Writer w;
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
    w.pod(s.background);
    return std::move(w.bytes());
}

Scene deserialize_scene(const std::string& bytes) {
    Reader r(bytes);
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
    s.background = r.pod<Vec3f>();
    if (!r.done()) throw Error("assimp sandbox: malformed reply");
    return s;
}

Scene import_assimp_isolated(const std::string& path) {
    int fds[2];
    if (pipe(fds) != 0) throw Error(path, 0, std::string("cannot create a pipe: ") + std::strerror(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        const int err = errno;
        close(fds[0]);
        close(fds[1]);
        throw Error(path, 0, std::string("cannot start the importer process: ") + std::strerror(err));
    }
    if (pid == 0) {
        close(fds[0]);
        run_child(path, fds[1]);
    }
    close(fds[1]);
    std::string reply;
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        reply.append(buffer, size_t(n));
    }
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status))
        throw Error(path, 0,
                    "the importer (assimp) crashed on this file (signal " +
                        std::to_string(WTERMSIG(status)) + "); the file is malformed or not supported");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error(path, 0, "the importer (assimp) failed on this file (exit status " +
                                 std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    Reader r(reply);
    if (reply.size() < sizeof(uint32_t) + 1 || r.pod<uint32_t>() != magic)
        throw Error(path, 0, "the importer (assimp) gave no answer");
    if (r.pod<Reply>() == Reply::error) throw Error(r.string());
    return deserialize_scene(reply.substr(sizeof(uint32_t) + 1));
}

}  // namespace rtt::detail
