#include "output_set.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "rtt/error.h"

namespace rtt::cli {
namespace fs = std::filesystem;

namespace {

std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
    return s;
}

fs::path folder_of(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? fs::path(".") : parent;
}

/// The same file whichever way it is spelled ("a.png", "./a.png", "dir/../a.png").
fs::path identity(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
}

}  // namespace

std::string extension_of(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

void OutputSet::add(const std::string& option, const std::string& path,
                    const std::vector<std::string>& extensions) {
    if (path.empty()) throw Error(option + ": empty file name");
    if (!extensions.empty() &&
        std::find(extensions.begin(), extensions.end(), extension_of(path)) == extensions.end())
        throw Error(option + ": cannot write '" + path + "': unknown extension '" +
                    extension_of(path) + "' (this option writes " + joined(extensions) + ")");
    for (const Entry& e : entries_)
        if (identity(e.path) == identity(path))
            throw Error(option + ": '" + path + "' is also the file of " + e.option +
                        "; give each output its own name");
    entries_.push_back({option, path, ""});
}

void OutputSet::check_writable() const {
    for (const Entry& e : entries_) {
        const std::string prefix = e.option + ": cannot write " + e.path + ": ";
        const fs::path folder = folder_of(e.path);
        std::error_code ec;
        if (!fs::is_directory(folder, ec))
            throw Error(prefix + "folder " + folder.string() + " does not exist");
        if (fs::is_directory(e.path, ec)) throw Error(prefix + "it is a folder");
        // Asked of the system rather than probed with a file: a run killed right after a probe
        // was created would leave it behind.
        if (::faccessat(AT_FDCWD, folder.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
            throw Error(prefix + "folder " + folder.string() + " is not writable (" +
                        std::strerror(errno) + ")");
    }
}

void OutputSet::write(const std::string& path,
                      const std::function<void(const std::string&)>& write) {
    auto it = std::find_if(entries_.begin(), entries_.end(),
                           [&](const Entry& e) { return e.path == path; });
    if (it == entries_.end())
        throw Error("internal: output " + path + " was not checked before the work");
    // Hidden, in the same folder, so the final rename is atomic.
    std::string name(".");  // appended, not "." + ...: GCC 12 warns falsely (-Wrestrict) on that
    name += fs::path(path).filename().string();
    name += ".rtt-" + std::to_string(::getpid());
    it->temporary = (folder_of(path) / name).string();
    write(it->temporary);
}

void OutputSet::commit() {
    std::vector<const Entry*> renamed;
    for (const Entry& e : entries_) {
        if (e.temporary.empty()) continue;
        std::error_code ec;
        fs::rename(e.temporary, e.path, ec);
        if (ec) {
            for (const Entry* done : renamed) fs::remove(done->path, ec);
            discard();
            throw Error(e.option + ": cannot write " + e.path + ": " + ec.message() +
                        " (no output of this run was kept)");
        }
        renamed.push_back(&e);
    }
    for (Entry& e : entries_) e.temporary.clear();
}

void OutputSet::discard() noexcept {
    for (Entry& e : entries_) {
        if (e.temporary.empty()) continue;
        std::error_code ec;
        fs::remove(e.temporary, ec);
        e.temporary.clear();
    }
}

}  // namespace rtt::cli
