// meter-controller: the vehicle-control process. A thin CLI11 front end over the library.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <iostream>
#include <optional>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/run/check_dbc_command.hpp"
#include "meter/controller/run/convert_log_command.hpp"
#include "meter/controller/run/decode_command.hpp"
#include "meter/controller/run/decode_e2e_command.hpp"
#include "meter/controller/run/dump_dbc_command.hpp"
#include "meter/controller/run/input_schemes.hpp"
#include "meter/controller/run/odometer_reset_command.hpp"
#include "meter/controller/run/run_command.hpp"
#include "meter/log_sinks/log_options.hpp"
#include "meter/log_sinks/open_log_sink.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/link_options.hpp"

namespace {

// decode and decode --e2e, their stderr through the process's log.
int decode_main(const std::string& dbc, const std::string& log, const std::string& map, const std::string& catalog, bool e2e,
                bool strict, const meter::log_sinks::LogOptions& log_options) {
  using namespace meter::controller;
  meter::log_sinks::ProcessLog process_log("meter-controller", log_options.sink, log_options.level, "decode");
  std::ostream& err = process_log.err();
  try {
    meter::protocol::use_catalog_option(catalog);
  } catch (const std::exception& e) {
    err << "meter-controller decode: " << e.what() << "\n";
    return 1;
  }
  if (e2e) return decode_e2e_command(dbc, log, map, std::cout, err, strict);
  return decode_command(dbc, log, map, std::cout, err, strict);
}

// convert-log. Its progress line redraws itself with a carriage return on a terminal: only where
// stderr is the terminal itself, not records (--log or --log-level given).
int convert_log_main(meter::controller::ConvertLogOptions& convert, const meter::log_sinks::LogOptions& log_options) {
  if (!log_options.given()) {
    convert.progress = ::isatty(2) != 0;
    return meter::controller::convert_log_command(convert, std::cout, std::cerr);
  }
  meter::log_sinks::ProcessLog process_log("meter-controller", log_options.sink, log_options.level, "convert-log");
  return meter::controller::convert_log_command(convert, std::cout, process_log.err());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace meter::controller;
  CLI::App app{"meter-controller: reads CAN (SocketCAN, recorded logs: candump, Vector ASC and BLF, PCAN TRC) or Modbus, decodes it with a DBC, "
               "conditions the signals and publishes the cluster state to meter-view."};
  app.require_subcommand(1);

  RunOptions run;
  auto* r = app.add_subcommand("run", "Run the controller daemon: input -> DBC decode -> mapping -> protocol link.");
  r->add_option("--dbc", run.dbcs,
                "DBC file describing the bus (not needed for a Modbus-only mapping); with several inputs "
                "NAME=FILE for the input of that name, once per CAN input");
  r->add_option("--map", run.map, "Mapping file: bus signals -> catalog signals (docs/mapping.md)")->required()->check(CLI::ExistingFile);
  const std::string input_help = "Input: " + input_forms_described() +
                                 ". Repeatable: several inputs are NAME=INPUT each (e.g. --input body=can:vcan0 "
                                 "--input chassis=can:vcan1), read on one clock (docs/controller.md)";
  r->add_option("--input", run.inputs, input_help)
      ->required()
      ->take_all();
  r->add_option("--replay", run.replay,
                "Log timing: realtime (original timing), fast (simulated clock, as fast as possible), "
                "scale:N (N times faster than recorded)")
      ->default_val("realtime");
  r->add_option("--link", run.link, "Where views connect: unix:/path or tcp:HOST:PORT (default: $XDG_RUNTIME_DIR/meter.sock)");
  r->add_option("--key-file", run.key_file, meter::protocol::kKeyFileHelp);
  r->add_flag("--insecure-link", run.insecure_link, meter::protocol::kInsecureLinkHelp);
  r->add_option("--state-dir", run.state_dir, "Directory for the persisted odometer (atomic writes); none = not persisted");
  r->add_flag("--exit-at-end", run.exit_at_end, "Exit when the log ends (default: keep running on a silent bus: the values time out)");
  r->add_option("--linger", run.linger_s, "With --exit-at-end: keep serving the final state this many seconds first")
      ->check(CLI::NonNegativeNumber);
  r->add_flag("-v,--verbose", run.verbose, "Print what is connected to what");
  r->add_option("--link-timeout", run.link_timeout_ms,
                "Milliseconds of silence after which a view counts as lost (heartbeats every third of it; "
                "the longer of the two sides' settings applies)")
      ->check(CLI::Range(30, 60000))
      ->capture_default_str();
  const char* strict_help = "Refuse every DBC quirk the lenient parser only warns about (docs/dbc.md)";
  r->add_flag("--strict", run.strict, strict_help);
  const char* catalog_help = "Signal catalog, a VSS JSON file (docs/catalog.md); default: the built-in "
                             "protocol/catalog/signals.vss.json";
  r->add_option("--catalog", run.catalog, catalog_help)->check(CLI::ExistingFile);
  r->add_option("--trace", run.trace,
                "Write a latency trace CSV (frames received, values published, link flushes; CLOCK_REALTIME ns)");
  r->add_option("--record", run.record,
                "Write every published change as a link recording stamped with the input's clock (with "
                "--replay fast: the simulated clock), which meter-view --play renders (docs/fleet.md)");
  meter::log_sinks::LogOptions log_options;  // one per process: only the command given parses
  meter::log_sinks::add_log_options(*r, log_options);
  r->add_option("--trace-json", run.trace_json,
                "Write a Chrome trace-event JSON (receive, decode, publish on CLOCK_MONOTONIC; opens in Perfetto UI)");

  std::string dbc, log, map;
  auto* d = app.add_subcommand("decode", "Decode a recorded CAN log (" + log_format_names() +
                                             ") with a DBC to CSV: timestamp,message,signal,raw,physical,unit,status.");
  d->add_option("--dbc", dbc, "DBC file")->required()->check(CLI::ExistingFile);
  d->add_option("LOG", log, "Recorded CAN log (" + log_format_names() + "; the format is told by the first lines, else by the extension)")->required()->check(CLI::ExistingFile);
  d->add_option("--map", map, "Only the signals this mapping uses")->check(CLI::ExistingFile);
  bool decode_strict = false;
  d->add_flag("--strict", decode_strict, strict_help);
  bool decode_e2e = false;
  d->add_flag("--e2e", decode_e2e,
              "Check end-to-end protection instead: each protected frame's checksum and counter as CSV "
              "(timestamp,message,checksum,received,expected,counter,counter_status,used), a summary per message "
              "on stderr; with --map its [e2e] sections, without what the DBC's conventions identify (docs/e2e.md). "
              "Exit 2 when a message looks misconfigured");
  std::string decode_catalog;
  d->add_option("--catalog", decode_catalog, catalog_help)->check(CLI::ExistingFile);
  meter::log_sinks::add_log_options(*d, log_options);

  std::string check;
  bool check_strict = false;
  auto* c = app.add_subcommand("check-dbc",
                               "Parse a DBC, summarise it, print the lint report (counts, warnings by kind) and every "
                               "problem (file:line). Exit 0 with warnings, 1 with errors.");
  c->add_option("DBC", check, "DBC file")->required()->check(CLI::ExistingFile);
  c->add_flag("--strict", check_strict, "Every problem is an error (exit 1)");

  ConvertLogOptions convert;
  auto* v = app.add_subcommand("convert-log", "Write a recorded CAN log (" + log_format_names() +
                                                  ") as candump -L, Vector ASC or Vector BLF (docs/logs.md).");
  v->add_option("IN", convert.in, "The log read (FILE#N: only its channel N)")->required();
  v->add_option("OUT", convert.out, "The file written; its format by its extension (.log candump, .asc, .blf) or --format")->required();
  v->add_option("--format", convert.format, "candump, asc or blf, whatever OUT is named");
  meter::log_sinks::add_log_options(*v, log_options);

  std::string dump;
  auto* u = app.add_subcommand("dump-dbc", "Print the parsed DBC as JSON: every message and signal field, value tables, warnings.");
  u->add_option("DBC", dump, "DBC file")->required()->check(CLI::ExistingFile);

  std::string reset_dir;
  std::optional<double> reset_km;
  auto* o = app.add_subcommand("odometer-reset",
                               "Accept the odometer state again after the controller refused it (both copies damaged, or a "
                               "copy put back from an older state): rewrites both copies (docs/controller.md).");
  o->add_option("--state-dir", reset_dir, "The controller's --state-dir")->required();
  o->add_option("--km", reset_km, "The distance to store; default: the largest one a valid copy holds")
      ->check(CLI::NonNegativeNumber);

  CLI11_PARSE(app, argc, argv);
  if (*r) {
    meter::log_sinks::ProcessLog log("meter-controller", log_options.sink, log_options.level, "run");  // every err line a record
    return run_command(run, std::cout, log.err());
  }
  if (*d) return decode_main(dbc, log, map, decode_catalog, decode_e2e, decode_strict, log_options);
  if (*v) return convert_log_main(convert, log_options);
  if (*u) return dump_dbc_command(dump, std::cout, std::cerr);
  if (*o) return odometer_reset_command(reset_dir, reset_km, std::cout, std::cerr);
  return check_dbc_command(check, std::cout, std::cerr, check_strict);
}
