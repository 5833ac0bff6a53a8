#include "command_output.hpp"

#include <cstdio>
#include <memory>

#include "meter/protocol/log/logger.hpp"

namespace meter::controller {

std::string csv_field(std::string_view s) {
  if (s.find_first_of(",\"\n") == std::string_view::npos) return std::string(s);
  std::string o = "\"";
  for (char c : s) {
    if (c == '"') o += '"';
    o += c;
  }
  return o + "\"";
}

std::string fmt_double(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

std::string hex(std::uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%X", v);
  return b;
}

void report_bad_lines(LogSource& log, const std::string& path, std::ostream& err) {
  constexpr std::size_t kShown = 10;
  auto shown = std::make_shared<std::size_t>(0);
  auto report = [shown, path, &err](const BadLine& b) {
    const auto file = protocol::log_field("file", path);
    if (*shown == 0) protocol::LogLine(err, protocol::LogLevel::Warning, "input", {file}) << path << ": bad line(s) skipped:\n";
    if (*shown < kShown)
      protocol::LogLine(err, protocol::LogLevel::Warning, "input", {file, protocol::log_field("line", static_cast<std::int64_t>(b.line))})
          << "  " << path << ":" << b.line << ": " << b.why << "\n";
    if (++*shown == kShown + 1)
      protocol::LogLine(err, protocol::LogLevel::Warning, "input", {file}) << "  " << path << ": more bad lines: counted, not shown\n";
  };
  for (const BadLine& b : log.records().bad_lines) report(b);
  log.on_bad_record(report);
}

void report_bad_line_count(const LogSource& log, const std::string& path, std::ostream& err) {
  if (log.bad_records())
    protocol::LogLine(err, protocol::LogLevel::Warning, "input", {protocol::log_field("file", path)})
        << path << ": skipped " << log.bad_records() << " bad line(s)\n";
}

void report_dbc_warnings(const Database& db, std::ostream& err) {
  if (db.warnings.empty()) return;
  const DbcWarning& w = db.warnings.front();
  protocol::LogLine(err, protocol::LogLevel::Warning, "dbc", {protocol::log_field("file", db.file), protocol::log_field("line", static_cast<std::int64_t>(w.line))})
      << db.file << ": " << db.warnings.size() << " DBC warning(s), first " << db.file << ":" << w.line << ": ["
      << to_string(w.kind) << "] " << w.text << "; 'meter-controller check-dbc " << db.file
      << "' lists them all, --strict refuses them\n";
}

bool load_dbc_reporting(const std::string& path, Database& db, std::ostream& err) {
  try {
    db = load_dbc(path);
    return true;
  } catch (const DbcError& e) {
    err << e.what() << "\n";
    return false;
  }
}

}  // namespace meter::controller
