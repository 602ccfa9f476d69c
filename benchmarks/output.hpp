#pragma once
/// \file What a run leaves behind: the stdout summary, and results.{csv,json}, builds.csv,
/// correctness.csv, disagreements.csv under the output directory.

#include "harness.hpp"

#include <map>
#include <string>

namespace cdbench {

/// CPU model, core count, compiler, build type and flags, FCL version, date (UTC): what makes a number
/// comparable to another.
[[nodiscard]] std::map<std::string, std::string> machine_info();

/// Summary tables to stdout: per mesh, protocol and mode, one row per distance class, one column per
/// method with median µs, p99 µs and the ratio to the peer; then the build table and the correctness table.
void print_summary(const Report& report);

/// Writes every file under report.options.out_dir (created if missing). Returns the paths written.
std::vector<std::string> write_outputs(const Report& report);

}  // namespace cdbench
