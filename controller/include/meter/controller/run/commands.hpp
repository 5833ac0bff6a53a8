// The meter-controller subcommands as library functions, so tests and benches can call them
// without a process, and app/main.cpp stays a thin CLI11 front end.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace meter::controller {

struct RunOptions {
  // One entry per input: [NAME=]log:FILE | can:IFACE | modbus-tcp:HOST:PORT | modbus-rtu:DEV:BAUD[:8N1];
  // with several, each has a NAME the mapping's INPUT.Message.Signal sources can use.
  std::vector<std::string> inputs;
  // [NAME=]FILE, one per CAN input (none for a Modbus-only mapping); see parse_input_specs().
  std::vector<std::string> dbcs;
  std::string map;
  std::string replay = "realtime";
  std::string link;        // empty: protocol::default_endpoint()
  std::string state_dir;   // empty: odometer not persisted
  bool exit_at_end = false;
  double linger_s = 0.0;
  bool verbose = false;
  // Silence on the link for this long = link lost (heartbeats every third of it). 300 ms suits
  // two processes on one machine; an inter-chip link through an emulator configures more.
  int link_timeout_ms = 300;
  // Latency trace (CSV): every received CAN frame, every published value change and every
  // flush to the link, on CLOCK_REALTIME (bench/latency reads it). Empty = off.
  std::string trace;
  bool strict = false;  // refuse every DBC quirk the lenient parser would only warn about
  // The signal catalog (VSS JSON, docs/catalog.md); empty: the built-in default.
  std::string catalog;
  // Chrome trace-event JSON (docs/tracing.md): receive, decode and publish spans on CLOCK_MONOTONIC,
  // the clock of the link's stamps and of meter-view's --trace-json. Empty = off.
  std::string trace_json;
  // Link recording of every published change stamped with the input's clock (the simulated one
  // under --replay fast), for meter-view --play (docs/fleet.md). Empty = off.
  std::string record;
};

// Runs the daemon until the input ends (with exit_at_end) or SIGINT/SIGTERM. Returns the exit code;
// errors are printed to err with what was expected.
int run_command(const RunOptions& options, std::ostream& out, std::ostream& err);

// decode: a candump log + DBC -> CSV rows "timestamp,message,signal,raw,physical,unit,status".
// With a mapping, only the signals the mapping uses are written.
// strict: refuse every DBC quirk (docs/dbc.md).
int decode_command(const std::string& dbc, const std::string& log, const std::string& map, std::ostream& out,
                   std::ostream& err, bool strict = false);

// check-dbc: parse a DBC, summarise it, print the lint report (counts, warnings by kind) and every
// problem with its file:line. 0 with warnings, 1 when it cannot be read or (strict) has any problem.
int check_dbc_command(const std::string& dbc, std::ostream& out, std::ostream& err, bool strict = false);

// dump-dbc: the parsed database as JSON (messages, signals with every field, value tables,
// warnings), for tools and the cross-check against other DBC parsers.
int dump_dbc_command(const std::string& dbc, std::ostream& out, std::ostream& err);

// odometer-reset: the explicit acceptance of a refused odometer state (both copies damaged, or a
// copy put back from an older state). Rewrites both copies in state_dir with km (whole kilometres
// or fractions), or without it with the largest distance any valid copy holds (never backwards).
// Returns 0, or 1 with the reason (no valid copy and no km given, an I/O error).
int odometer_reset_command(const std::string& state_dir, std::optional<double> km, std::ostream& out, std::ostream& err);

}  // namespace meter::controller
