#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "meter/log_sinks/open_log_sink.hpp"

namespace meter::log_sinks {

std::optional<SinkKind> parse_sink_kind(std::string_view text) {
  if (text == "text") return SinkKind::Text;
  if (text == "json") return SinkKind::Json;
  if (text == "journal") return SinkKind::Journal;
  if (text == "dlt") return SinkKind::Dlt;
  return std::nullopt;
}

SinkKind default_sink_kind(const char* journal_stream, bool stderr_known, unsigned long long stderr_dev,
                           unsigned long long stderr_ino) {
  if (journal_stream == nullptr || !stderr_known) return SinkKind::Text;
  const std::string_view s(journal_stream);
  const auto colon = s.find(':');
  if (colon == std::string_view::npos) return SinkKind::Text;
  unsigned long long dev = 0, ino = 0;
  const auto d = std::from_chars(s.data(), s.data() + colon, dev);
  const auto i = std::from_chars(s.data() + colon + 1, s.data() + s.size(), ino);
  if (d.ec != std::errc{} || d.ptr != s.data() + colon || i.ec != std::errc{} || i.ptr != s.data() + s.size())
    return SinkKind::Text;
  return dev == stderr_dev && ino == stderr_ino ? SinkKind::Journal : SinkKind::Text;
}

SinkKind default_sink_kind_here() {
  struct stat st {};
  const bool known = fstat(STDERR_FILENO, &st) == 0;
  return default_sink_kind(std::getenv("JOURNAL_STREAM"), known, known ? st.st_dev : 0, known ? st.st_ino : 0);
}

void configure_process_logging(const std::string& program, const std::string& sink, const std::string& level) {
  const auto threshold = level.empty() ? protocol::LogLevel::Info : protocol::parse_log_level(level);
  if (!threshold) throw std::invalid_argument("--log-level: expected error, warning, info or debug, got '" + level + "'");
  const auto kind = sink.empty() ? default_sink_kind_here() : parse_sink_kind(sink);
  if (!kind) throw std::invalid_argument("--log: expected text, json, journal or dlt, got '" + sink + "'");
  std::unique_ptr<protocol::RecordSink> out;
  switch (*kind) {
    case SinkKind::Text: out = protocol::make_stream_sink(std::cerr, protocol::LogForm::Text, program); break;
    case SinkKind::Json: out = protocol::make_stream_sink(std::cerr, protocol::LogForm::Json, program); break;
    case SinkKind::Journal: out = make_journal_sink(program); break;
    case SinkKind::Dlt: out = make_dlt_sink(program, *threshold); break;
  }
  protocol::configure_logging(program, *threshold, std::move(out));
}

ProcessLog::ProcessLog(const std::string& program, const std::string& sink, const std::string& level, std::string component)
    : program_(program), stream_(protocol::LogLevel::Info, std::move(component)) {
  configure_process_logging(program, sink, level);
}

ProcessLog::~ProcessLog() {
  stream_.end_line();
  protocol::configure_logging(program_, protocol::LogLevel::Info, nullptr);
}

}  // namespace meter::log_sinks
