#include "cli_hints.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace rtt::cli {
namespace {

/// The innermost subcommand the user reached ("rtt render ..." -> render).
const CLI::App* innermost(const CLI::App& app) {
    const CLI::App* at = &app;
    for (;;) {
        const auto chosen = at->get_subcommands();
        if (chosen.empty()) return at;
        at = chosen.front();
    }
}

std::string command_path(const CLI::App* app) {
    std::string path;
    for (const CLI::App* a = app; a; a = a->get_parent())
        path = a->get_name() + (path.empty() ? "" : " ") + path;
    return path;
}

/// The candidate nearest to `word`, if near enough to be a typo.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
    for (const std::string& c : candidates) {
        const size_t d = edit_distance(word, c);
        if (d < best_distance) best_distance = d, best = c;
    }
    return best;
}

std::vector<std::string> option_names(const CLI::App* app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app->get_options()) {
        for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
        for (const std::string& s : o->get_snames()) names.push_back("-" + s);
    }
    return names;
}

std::vector<std::string> subcommand_names(const CLI::App* app) {
    std::vector<std::string> names;
    for (const CLI::App* s : app->get_subcommands({})) names.push_back(s->get_name());
    return names;
}

std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
    return s;
}

}  // namespace

size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    std::iota(row.begin(), row.end(), size_t(0));
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] =
                std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = up;
        }
    }
    return row[b.size()];
}

std::string hint_for(const CLI::App& app, const CLI::ParseError& error) {
    const CLI::App* at = innermost(app);
    const std::string help = " See '" + command_path(at) + " --help'.";
    if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
        // Unknown options fall through to the parent (main.cpp: global options like --isa).
        std::vector<std::string> extras;
        for (const CLI::App* a = at; a; a = a->get_parent())
            for (const std::string& extra : a->remaining()) extras.push_back(extra);
        std::string hints;
        for (const std::string& extra : extras) {
            const bool option = !extra.empty() && extra[0] == '-';
            const std::string word = option ? extra.substr(0, extra.find('=')) : extra;
            const std::string guess =
                nearest(word, option ? option_names(at) : subcommand_names(at));
            if (!guess.empty()) hints += " Did you mean " + guess + " instead of " + word + "?";
        }
        return hints + help;
    }
    if (dynamic_cast<const CLI::RequiredError*>(&error) && at->get_require_subcommand_min() > 0 &&
        at->get_subcommands().empty())
        return " '" + command_path(at) + "' needs one of: " + joined(subcommand_names(at)) + "." +
               help;
    return help;
}

}  // namespace rtt::cli
