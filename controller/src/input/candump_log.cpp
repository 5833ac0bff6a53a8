// A candump -L log file split into lines; bad lines are kept with their number and the reason.
// The candump entry of the log formats (log_format.hpp).

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/candump_log.hpp"

namespace meter::controller {

ParsedLog parse_candump_log(std::string_view text) {
  ParsedLog log;
  std::size_t pos = 0;
  std::string why;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++log.lines;
    const std::string_view t = trim_line_end(line);
    if (t.empty()) continue;  // blank lines are not errors
    auto r = parse_candump_line(t, &why);
    if (!r) {
      log.bad_lines.push_back({log.lines, why});
      continue;
    }
    log.frames.push_back(r->frame);
  }
  return log;
}

ParsedLog load_candump_log(const std::string& path) { return parse_candump_log(read_log_file(path)); }

bool sniff_candump_log(std::string_view head) {
  // The first few complete lines: a damaged first line still leaves the file recognisable, and a
  // line cut at the end of the head is not judged.
  constexpr int kLinesAsked = 8;
  int asked = 0;
  std::size_t pos = 0;
  std::string why;
  while (asked < kLinesAsked) {
    const std::size_t nl = head.find('\n', pos);
    if (nl == std::string_view::npos && head.size() >= kLogSniffBytes) break;
    const std::string_view line = trim_line_end(head.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
    if (!line.empty()) {
      ++asked;
      if (parse_candump_line(line, &why)) return true;
    }
    if (nl == std::string_view::npos) break;
    pos = nl + 1;
  }
  return false;
}

const LogFormat& candump_log_format() {
  static constexpr std::string_view kExtensions[] = {".log"};
  static const LogFormat format{"candump", "(1631416514.717133) can0 0D2#0000FFFF10000000", kExtensions,
                                sniff_candump_log, parse_candump_log};
  return format;
}

}  // namespace meter::controller
