#include "command_output.hpp"

#include <cstdio>

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

void report_bad_lines(const ParsedLog& log, const std::string& path, std::ostream& err) {
  if (log.bad_lines.empty()) return;
  protocol::LogLine(err, protocol::LogLevel::Warning, "input", {protocol::log_field("file", path)}) << path << ": skipped " << log.bad_lines.size() << " bad line(s)\n";
  std::size_t shown = 0;
  for (const auto& b : log.bad_lines) {
    if (++shown > 10) {
      protocol::LogLine(err, protocol::LogLevel::Warning, "input", {protocol::log_field("file", path)}) << "  ... and " << log.bad_lines.size() - 10 << " more\n";
      break;
    }
    protocol::LogLine(err, protocol::LogLevel::Warning, "input", {protocol::log_field("file", path), protocol::log_field("line", static_cast<std::int64_t>(b.line))}) << "  " << path << ":" << b.line << ": " << b.why << "\n";
  }
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
