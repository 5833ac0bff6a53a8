// The sinks a process can log to, chosen by main's --log (text, json, journal, dlt) and --log-level.
// Apart from the protocol library (its dev kit does not carry libsystemd's journal or libdlt).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "meter/protocol/log/logger.hpp"

namespace meter::log_sinks {

enum class SinkKind { Text, Json, Journal, Dlt };

// "text", "json", "journal", "dlt"; nothing for any other text.
std::optional<SinkKind> parse_sink_kind(std::string_view text);

// With no --log: the journal when JOURNAL_STREAM ("DEV:INODE", set by systemd for a service whose
// stderr it reads) names the device and inode stderr is open on, else plain text.
SinkKind default_sink_kind(const char* journal_stream, bool stderr_known, unsigned long long stderr_dev,
                           unsigned long long stderr_ino);
// The same for this process's stderr and environment.
SinkKind default_sink_kind_here();

std::unique_ptr<protocol::RecordSink> make_journal_sink(std::string program);
std::unique_ptr<protocol::RecordSink> make_dlt_sink(std::string program, protocol::LogLevel threshold);

// Sets the process's logger from main's options: `sink` empty = the default above; `level` empty =
// info. Throws std::invalid_argument naming the option and the values it takes.
void configure_process_logging(const std::string& program, const std::string& sink, const std::string& level);

// What a program's main holds while it runs: the logger set from its options and the stream its
// code writes `err` lines to (each line a record of `component` at level info). On destruction the
// logger goes back to plain text on stderr, closing the journal or DLT while libdlt still runs.
class ProcessLog {
 public:
  ProcessLog(const std::string& program, const std::string& sink, const std::string& level, std::string component);
  ~ProcessLog();
  ProcessLog(const ProcessLog&) = delete;
  ProcessLog& operator=(const ProcessLog&) = delete;
  std::ostream& err() { return stream_; }

 private:
  std::string program_;
  protocol::LogStream stream_;
};

// The options' help texts, one wording for every program.
inline constexpr const char* kLogHelp =
    "Where log records go: text (plain lines on stderr, the default), json (one JSON object a line on stderr), "
    "journal (the systemd journal with its fields; the default when stderr is the journal's stream), dlt "
    "(COVESA DLT through libdlt; docs/logging.md)";
inline constexpr const char* kLogLevelHelp = "Lowest level logged: error, warning, info (the default) or debug";

}  // namespace meter::log_sinks
