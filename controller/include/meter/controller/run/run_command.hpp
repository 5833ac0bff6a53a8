// meter-controller run: the daemon, input(s) -> model -> protocol link, and its options.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace meter::controller {

struct RunOptions {
  // One entry per input: [NAME=]SCHEME:ADDRESS, a scheme of run/input_schemes.hpp (log:FILE |
  // can:IFACE | modbus-tcp:HOST:PORT | modbus-rtu:DEV:BAUD[:8N1]); with several, each has a NAME the
  // mapping's INPUT.Message.Signal sources can use.
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
  std::string key_file;        // the link's key file (MAC on every frame); empty = none
  bool insecure_link = false;  // allow TCP without a key file (a lab)
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

}  // namespace meter::controller
