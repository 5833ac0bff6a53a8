// --log and --log-level, registered the same way on every program and every long-running command
// (meter-controller run, decode, convert-log; meter-view in all its modes): one wording, one check.
// For mains only: it needs CLI11, which they link (meter_cli); the library stays without it.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "meter/log_sinks/open_log_sink.hpp"

namespace meter::log_sinks {

struct LogOptions {
  std::string sink;   // empty: default_sink_kind_here()
  std::string level;  // empty: info
  bool given() const { return !sink.empty() || !level.empty(); }
};

// Adds --log and --log-level to `command` (a program, or one of its subcommands).
inline void add_log_options(CLI::App& command, LogOptions& options) {
  command.add_option("--log", options.sink, kLogHelp)->check(CLI::IsMember({"text", "json", "journal", "dlt"}));
  command.add_option("--log-level", options.level, kLogLevelHelp)->check(CLI::IsMember({"error", "warning", "info", "debug"}));
}

}  // namespace meter::log_sinks
