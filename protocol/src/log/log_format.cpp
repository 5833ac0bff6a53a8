#include "meter/protocol/log/log_format.hpp"

#include <cctype>
#include <ctime>

#include <nlohmann/json.hpp>

namespace meter::protocol {

namespace {

// UTC, microseconds: 2026-12-06T09:50:01.123456Z.
std::string iso_time(std::int64_t time_ns) {
  const std::time_t s = static_cast<std::time_t>(time_ns / 1000000000);
  const unsigned us = static_cast<unsigned>((time_ns % 1000000000) / 1000) % 1000000U;
  std::tm tm{};
  gmtime_r(&s, &tm);
  char b[96];
  std::snprintf(b, sizeof b, "%04d-%02d-%02dT%02d:%02d:%02d.%06uZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, us);
  return b;
}

std::string upper_key(std::string_view key) {
  std::string k;
  for (char c : key) k += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : '_';
  return k;
}

}  // namespace

std::string format_text(const LogRecord& r) { return r.prefix + r.message; }

std::string format_json(const LogRecord& r, std::string_view program) {
  nlohmann::ordered_json j;
  j["time"] = iso_time(r.time_ns);
  j["level"] = std::string(to_string(r.level));
  j["program"] = std::string(program);
  j["component"] = r.component;
  j["message"] = r.message;
  for (const LogField& f : r.fields) {
    // A field never hides the record's own keys.
    if (j.contains(f.key)) continue;
    if (f.number) j[f.key] = nlohmann::ordered_json::parse(f.value, nullptr, false);
    else j[f.key] = f.value;
  }
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

int journal_priority(LogLevel level) {
  switch (level) {
    case LogLevel::Error: return 3;
    case LogLevel::Warning: return 4;
    case LogLevel::Info: return 6;
    case LogLevel::Debug: return 7;
  }
  return 6;
}

std::vector<std::string> journal_fields(const LogRecord& r, std::string_view program) {
  std::vector<std::string> out;
  out.push_back("MESSAGE=" + r.message);
  out.push_back("PRIORITY=" + std::to_string(journal_priority(r.level)));
  if (!program.empty()) out.push_back("SYSLOG_IDENTIFIER=" + std::string(program));
  if (!r.code_file.empty()) {
    out.push_back("CODE_FILE=" + r.code_file);
    out.push_back("CODE_LINE=" + std::to_string(r.code_line));
  }
  out.push_back("METER_COMPONENT=" + r.component);
  for (const LogField& f : r.fields) out.push_back("METER_" + upper_key(f.key) + "=" + f.value);
  return out;
}

std::string dlt_app_id(std::string_view program) {
  if (program == "meter-controller") return "MCTL";
  if (program == "meter-view") return "MVEW";
  return "MTOL";
}

std::string dlt_context_id(std::string_view component) {
  // Every component the programs log from has its own id; one more becomes its first four letters
  // in upper case (docs/logging.md).
  static const std::pair<std::string_view, std::string_view> kIds[] = {
      {"run", "RUN"},      {"input", "INPT"}, {"health", "HLTH"}, {"e2e", "E2E"},      {"dbc", "DBC"},
      {"model", "MODL"},   {"link", "LINK"},  {"service", "SRVC"}, {"view", "VIEW"},   {"pipeline", "PIPE"},
      {"integrity", "INTG"}, {"display", "DISP"}, {"script", "SCRP"}, {"package", "PKG"}, {"governor", "GOVR"},
      {"render", "REND"}};
  for (const auto& [name, id] : kIds)
    if (component == name) return std::string(id);
  std::string id = upper_key(component.substr(0, 4));
  return id.empty() ? "MAIN" : id;
}

}  // namespace meter::protocol
