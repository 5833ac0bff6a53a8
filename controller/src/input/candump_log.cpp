// A candump -L log file split into lines; bad lines are kept with their number and the reason.
#include <fstream>
#include <sstream>
#include <stdexcept>

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
    std::string_view t = line;
    while (!t.empty() && (t.back() == '\r' || t.back() == ' ' || t.back() == '\t')) t.remove_suffix(1);
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

ParsedLog load_candump_log(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the log for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_candump_log(ss.str());
}

}  // namespace meter::controller
