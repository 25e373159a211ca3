// Shared by the fuzz targets: a private scratch folder for the files a target feeds to rtt's
// path-based readers, and the rule every target enforces: bad input may only end in rtt::Error.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "rtt/error.h"

namespace rtt::fuzz {

/// A folder of its own for this process (several fuzzers may run side by side); never removed
/// while the process runs, so libFuzzer's crash reproduction can reuse it.
inline const std::filesystem::path& scratch_dir() {
    static const std::filesystem::path dir = [] {
        std::string tmpl = (std::filesystem::temp_directory_path() / "rtt-fuzz-XXXXXX").string();
        if (!mkdtemp(tmpl.data())) std::abort();
        return std::filesystem::path(tmpl);
    }();
    return dir;
}

/// Writes `data` to `name` in the scratch folder and returns its path.
inline std::string write_file(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = (scratch_dir() / name).string();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    return path;
}

/// A property that must hold for every input: abort (a libFuzzer crash) with a message.
inline void require(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "rtt fuzz: property violated: %s\n", what);
    std::abort();
}

/// Runs `body`; rtt::Error is the expected answer to bad input. Any other exception is a bug
/// (an escaped std::out_of_range, bad_alloc from an unchecked size, ...): it aborts.
template <typename Fn>
void expect_only_rtt_errors(Fn&& body) {
    try {
        body();
    } catch (const Error&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtt fuzz: unexpected exception (not rtt::Error): %s\n", e.what());
        std::abort();
    }
}

}  // namespace rtt::fuzz
