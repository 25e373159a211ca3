// What to add to a command-line error so the user can fix it without reading the manual: the
// nearest option or subcommand to a mistyped one, the subcommands of a command that needs one,
// and where the help is.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace rtt::cli {

/// Extra sentences for `error` raised while parsing `app` (may be empty).
std::string hint_for(const CLI::App& app, const CLI::ParseError& error);

/// Levenshtein distance (insertions, deletions, substitutions), for "did you mean".
size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace rtt::cli
