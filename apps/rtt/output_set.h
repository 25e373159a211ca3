// The files one command writes, as a set: every destination checked before any work (folder
// exists and is writable, names differ, known extension), then written to temporaries and
// renamed into place together at the end. If one output fails, none of the run's is left.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace rtt::cli {

class OutputSet {
public:
    /// Records `path` for `option` ("-o", "--hits", ...). `extensions` lists what the option
    /// writes (".png", ".exr", ...; empty = any). Throws rtt::Error naming the option and the
    /// path for an unknown extension or a path given twice.
    void add(const std::string& option, const std::string& path,
             const std::vector<std::string>& extensions = {});

    /// Probes every destination folder (creates and removes a file in it). Throws rtt::Error
    /// "<option>: cannot write <path>: <reason>" for the first that fails.
    void check_writable() const;

    /// Writes `path` (one of those added) by calling write(temporary path); the file appears
    /// under its name only at commit(). The temporary's name does not keep the extension: a
    /// writer choosing a format takes it from `path`.
    void write(const std::string& path, const std::function<void(const std::string&)>& write);

    /// Renames every written temporary into place. On failure, removes what this set wrote.
    void commit();

    /// Removes the temporaries written so far (called when the run fails before commit).
    void discard() noexcept;

    ~OutputSet() { discard(); }

private:
    struct Entry {
        std::string option, path, temporary;
    };
    std::vector<Entry> entries_;
};

/// The lower-case extension of `path` with its dot (".png"), or "".
std::string extension_of(const std::string& path);

}  // namespace rtt::cli
