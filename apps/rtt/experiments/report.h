// Presenting measurements: aligned text tables for the terminal, the same tables as Markdown,
// and JSON holding every figure (per tracer and kind: time on both clocks, every repetition,
// counters, differences from the baseline) plus the machine it was measured on.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiments/machine_info.h"
#include "experiments/measure.h"

namespace rtt::bench {

/// A table as strings: the same content goes to the terminal and to Markdown.
struct TextTable {
    std::string title;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> notes;  ///< Printed under the table.
};

/// Columns padded to their widest cell, the first column left-aligned, the others right.
void print_table(std::FILE* out, const TextTable& table);
/// A GitHub Markdown table with the title in bold above and the notes below.
std::string markdown_table(const TextTable& table);

// Cell formatting used by every table.
std::string format_ms(double seconds);                 ///< "12.3" (milliseconds)
std::string format_ratio(double ratio);                ///< "1.23x", "-" for 0
std::string format_count(uint64_t n);                  ///< "1,234,567"
std::string format_fixed(double value, int decimals);  ///< "3.25"

/// Every figure of a measurement (see file comment).
nlohmann::json measurement_json(const Measurement& m);
nlohmann::json machine_json(const MachineInfo& m);
nlohmann::json table_json(const TextTable& table);
/// The inverses of measurement_json and table_json (a distributed `rtt bench` sends results
/// between ranks as this JSON). Throw nlohmann::json's exceptions on a malformed document.
Measurement measurement_from_json(const nlohmann::json& j);
TextTable table_from_json(const nlohmann::json& j);

/// Writes `j` (indented) to `path`, whole or not at all. Throws rtt::Error on I/O failure.
void write_json_file(const std::string& path, const nlohmann::json& j);

/// One line for logs: "room 640x480 1x1, 1 thread: 3 reps, 1.2 s; mismatches 0".
std::string measurement_summary(const Measurement& m);

/// The differences from the baseline over a set of measurements, one note per tracer:
/// "rtt vs packet: 0 mismatches in 921,600 primary rays and 0 in 1,234,567 shadow segments";
/// for inexact tracers (Embree) they are labelled as ties.
std::vector<std::string> agreement_notes(const std::vector<Measurement>& ms);

}  // namespace rtt::bench
