#include "experiments/report.h"

#include <algorithm>
#include <cinttypes>

#include "rtt/io.h"

namespace rtt::bench {

void print_table(std::FILE* out, const TextTable& table) {
    std::vector<size_t> width(table.header.size(), 0);
    auto widen = [&](const std::vector<std::string>& row) {
        for (size_t c = 0; c < row.size() && c < width.size(); ++c)
            width[c] = std::max(width[c], row[c].size());
    };
    widen(table.header);
    for (const auto& row : table.rows) widen(row);
    auto line = [&](const std::vector<std::string>& row) {
        std::string s;
        for (size_t c = 0; c < width.size(); ++c) {
            const std::string cell = c < row.size() ? row[c] : "";
            const std::string pad(width[c] - std::min(width[c], cell.size()), ' ');
            s += c == 0 ? cell + pad : "  " + pad + cell;
        }
        while (!s.empty() && s.back() == ' ') s.pop_back();
        std::fprintf(out, "%s\n", s.c_str());
    };
    if (!table.title.empty()) std::fprintf(out, "\n%s\n", table.title.c_str());
    line(table.header);
    size_t total = 0;
    for (size_t w : width) total += w + 2;
    std::fprintf(out, "%s\n", std::string(total > 2 ? total - 2 : 0, '-').c_str());
    for (const auto& row : table.rows) line(row);
    for (const std::string& note : table.notes) std::fprintf(out, "  %s\n", note.c_str());
    std::fflush(out);
}

std::string markdown_table(const TextTable& table) {
    std::string s;
    if (!table.title.empty()) s += "**" + table.title + "**\n\n";
    auto line = [&](const std::vector<std::string>& row) {
        s += "|";
        for (size_t c = 0; c < table.header.size(); ++c)
            s += " " + (c < row.size() ? row[c] : "") + " |";
        s += "\n";
    };
    line(table.header);
    s += "|";
    for (size_t c = 0; c < table.header.size(); ++c) s += c == 0 ? "---|" : "---:|";
    s += "\n";
    for (const auto& row : table.rows) line(row);
    if (!table.notes.empty()) {
        s += "\n";
        for (const std::string& note : table.notes) s += "- " + note + "\n";
    }
    return s;
}

std::string format_fixed(double value, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

std::string format_ms(double seconds) {
    const double ms = seconds * 1e3;
    return format_fixed(ms, ms < 10 ? 2 : 1);
}

std::string format_ratio(double ratio) {
    return ratio > 0 ? format_fixed(ratio, 2) + "x" : "-";
}

std::string format_count(uint64_t n) {
    std::string digits = std::to_string(n), s;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
        s += digits[i];
    }
    return s;
}

namespace {

nlohmann::json clocks_json(const Clocks& c) {
    return {{"wall_s", c.wall}, {"cpu_s", c.cpu}};
}

nlohmann::json kind_json(const KindResult& k) {
    nlohmann::json reps = nlohmann::json::array();
    for (const Clocks& c : k.reps) reps.push_back(clocks_json(c));
    const TraceStats& s = k.stats;
    const RttStats& r = k.rtt;
    nlohmann::json declined = nlohmann::json::object();
    for (const auto& [name, field] : declined_fields) declined[name] = r.*field;
    return {{"rays", k.rays},
            {"time", clocks_json(k.time)},
            {"mrays_per_s_cpu", k.mrays_per_second(ClockKind::cpu)},
            {"mrays_per_s_wall", k.mrays_per_second(ClockKind::wall)},
            {"repetitions", reps},
            {"differences_from_baseline", k.differences},
            {"stats",
             {{"tiles", s.tiles},
              {"rtt_tiles", r.rtt_tiles},
              {"rays", s.rays},
              {"traced", s.traced},
              {"answered", r.answered},
              {"relevant_sum", r.relevant_sum},
              {"avg_relevant", r.avg_relevant()},
              {"fallback_seconds", r.fallback_seconds()},
              {"declined", declined}}}};
}

Clocks clocks_from_json(const nlohmann::json& j) {
    return Clocks{j.at("wall_s").get<double>(), j.at("cpu_s").get<double>()};
}

KindResult kind_from_json(const nlohmann::json& j) {
    KindResult k;
    k.rays = j.at("rays").get<uint64_t>();
    k.time = clocks_from_json(j.at("time"));
    for (const nlohmann::json& c : j.at("repetitions")) k.reps.push_back(clocks_from_json(c));
    k.differences = j.at("differences_from_baseline").get<uint64_t>();
    const nlohmann::json& s = j.at("stats");
    TraceStats& t = k.stats;
    RttStats& r = k.rtt;
    for (auto [field, name] : {std::pair{&t.tiles, "tiles"},
                               {&r.rtt_tiles, "rtt_tiles"},
                               {&t.rays, "rays"},
                               {&t.traced, "traced"},
                               {&r.answered, "answered"},
                               {&r.relevant_sum, "relevant_sum"}})
        *field = s.at(name).get<uint64_t>();
    if (s.contains("fallback_seconds"))
        r.fallback_ns = uint64_t(s.at("fallback_seconds").get<double>() * 1e9 + 0.5);
    if (s.contains("declined")) {  // files written before the counters existed lack them
        const nlohmann::json& d = s.at("declined");
        for (const auto& [name, field] : declined_fields) r.*field = d.at(name).get<uint64_t>();
    }
    return k;
}

}  // namespace

Measurement measurement_from_json(const nlohmann::json& j) {
    Measurement m;
    m.scene = j.at("scene").get<std::string>();
    m.width = j.at("width").get<int>();
    m.height = j.at("height").get<int>();
    m.aa = j.at("aa").get<int>();
    m.threads = j.at("threads").get<int>();
    m.repetitions = j.at("repetitions").get<int>();
    m.baseline = j.at("baseline").get<std::string>();
    m.primary_rays = j.at("primary_rays").get<uint64_t>();
    m.shadow_rays = j.at("shadow_rays").get<uint64_t>();
    m.shadow_tiles = j.at("shadow_tiles").get<size_t>();
    m.seconds = j.at("seconds").get<double>();
    for (const nlohmann::json& t : j.at("tracers"))
        m.tracers.push_back({t.at("kind").get<std::string>(), t.at("exact").get<bool>(),
                             kind_from_json(t.at("primary")), kind_from_json(t.at("shadow"))});
    return m;
}

TextTable table_from_json(const nlohmann::json& j) {
    return TextTable{j.at("title").get<std::string>(),
                     j.at("header").get<std::vector<std::string>>(),
                     j.at("rows").get<std::vector<std::vector<std::string>>>(),
                     j.at("notes").get<std::vector<std::string>>()};
}

nlohmann::json measurement_json(const Measurement& m) {
    nlohmann::json tracers = nlohmann::json::array();
    for (const TracerResult& t : m.tracers)
        tracers.push_back({{"kind", t.kind},
                           {"exact", t.exact},
                           {"primary", kind_json(t.primary)},
                           {"shadow", kind_json(t.shadow)}});
    return {{"scene", m.scene},
            {"width", m.width},
            {"height", m.height},
            {"aa", m.aa},
            {"threads", m.threads},
            {"repetitions", m.repetitions},
            {"baseline", m.baseline},
            {"primary_rays", m.primary_rays},
            {"shadow_rays", m.shadow_rays},
            {"shadow_tiles", m.shadow_tiles},
            {"mismatches", m.mismatches()},
            {"seconds", m.seconds},
            {"tracers", tracers}};
}

nlohmann::json machine_json(const MachineInfo& m) {
    return {{"cpu_model", m.cpu_model},
            {"logical_cpus", m.logical_cpus},
            {"isa", m.isa},
            {"simd_width", m.simd_width},
            {"compiler", m.compiler},
            {"git_commit", m.git_commit},
            {"date", m.date},
            {"load_average_1min", m.load_average}};
}

nlohmann::json table_json(const TextTable& table) {
    return {{"title", table.title},
            {"header", table.header},
            {"rows", table.rows},
            {"notes", table.notes}};
}

void write_json_file(const std::string& path, const nlohmann::json& j) {
    const std::string text = j.dump(2) + "\n";
    write_file_atomically(path, [&](std::FILE* f) { std::fwrite(text.data(), 1, text.size(), f); });
}

std::string measurement_summary(const Measurement& m) {
    char text[256];
    std::snprintf(
        text, sizeof text, "%s %dx%d %dx%d, %d thread%s: %d rep%s, %.1f s; mismatches %" PRIu64,
        m.scene.c_str(), m.width, m.height, m.aa, m.aa, m.threads, m.threads == 1 ? "" : "s",
        m.repetitions, m.repetitions == 1 ? "" : "s", m.seconds, m.mismatches());
    return text;
}

std::vector<std::string> agreement_notes(const std::vector<Measurement>& ms) {
    struct Sum {
        std::string kind, baseline;
        bool exact = true;
        uint64_t primary = 0, primary_rays = 0, shadow = 0, shadow_rays = 0;
    };
    std::vector<Sum> sums;
    for (const Measurement& m : ms)
        for (const TracerResult& t : m.tracers) {
            if (t.kind == m.baseline) continue;
            auto it = std::find_if(sums.begin(), sums.end(), [&](const Sum& s) {
                return s.kind == t.kind && s.baseline == m.baseline;
            });
            if (it == sums.end()) it = sums.insert(sums.end(), Sum{t.kind, m.baseline, t.exact});
            it->primary += t.primary.differences;
            it->primary_rays += t.primary.rays;
            it->shadow += t.shadow.differences;
            it->shadow_rays += t.shadow.rays;
        }
    std::vector<std::string> notes;
    for (const Sum& s : sums)
        notes.push_back(s.kind + " vs " + s.baseline + ": " + format_count(s.primary) + " of " +
                        format_count(s.primary_rays) + " primary hits and " +
                        format_count(s.shadow) + " of " + format_count(s.shadow_rays) +
                        " shadow answers differ" +
                        (s.exact ? (s.primary + s.shadow == 0 ? " (exact)" : " -- MISMATCHES")
                                 : " (Embree: own arithmetic, may break exact ties differently)"));
    return notes;
}

}  // namespace rtt::bench
