// A candump -L log file split into lines; bad lines are kept with their number and the reason.
// The candump entry of the log formats (log_format.hpp).

#include "meter/controller/input/candump_log.hpp"

#include <algorithm>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_lines.hpp"
#include "meter/controller/input/write_log_chunks.hpp"

namespace meter::controller {
namespace {

// One candump log being read: its interfaces become channels 1, 2, ... in order of appearance.
class CandumpReader {
 public:
  explicit CandumpReader(ParsedLog& window) : log(window) {}
  void line(std::string_view t) {
    ++log.lines;
    if (t.empty()) return;  // blank lines are not errors
    auto r = parse_candump_line(t, &why_);
    if (!r) {
      log.bad_lines.push_back({log.lines, why_});
      return;
    }
    r->frame.channel = channel_of(r->interface);
    log.frames.push_back(r->frame);
  }
  ParsedLog& log;

 private:
  std::string why_;
  std::vector<std::string> interfaces_;
  std::uint8_t channel_of(const std::string& name) {
    auto it = std::find(interfaces_.begin(), interfaces_.end(), name);
    if (it == interfaces_.end()) {
      if (interfaces_.size() == 255) return 255;  // more interfaces than channels: the last one holds the rest
      interfaces_.push_back(name);
      it = interfaces_.end() - 1;
    }
    return static_cast<std::uint8_t>(it - interfaces_.begin() + 1);
  }
};

}  // namespace

std::unique_ptr<LogSource> open_candump_log(std::istream& in) { return std::make_unique<TextLogSource<CandumpReader>>(in); }

ParsedLog read_candump_log(std::istream& in) { return read_whole_log(*open_candump_log(in)); }

ParsedLog parse_candump_log(std::string_view text) {
  std::istringstream in{std::string(text)};
  return read_candump_log(in);
}

ParsedLog load_candump_log(const std::string& path) {
  std::ifstream in(path, std::ios::binary);  // read a block at a time, as run and decode read it
  if (!in) throw std::runtime_error(path + ": cannot open the log for reading");
  return read_candump_log(in);
}

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

std::string candump_interface(const CanFrame& frame) {
  return "can" + std::to_string(frame.channel > 0 ? frame.channel - 1 : 0);
}

std::size_t write_candump_log(LogSource& frames, std::ostream& out, const LogProgress& progress) {
  return write_log_chunks(
      frames, kLogTextChunk,
      [](const CanFrame& f, std::string& text) {
        text += format_candump_line(f, candump_interface(f));
        text += '\n';
      },
      write_to(out), progress);
}

const LogFormat& candump_log_format() {
  static constexpr std::string_view kExtensions[] = {".log"};
  static const LogFormat format{"candump", "(1631416514.717133) can0 0D2#0000FFFF10000000", kExtensions,
                                sniff_candump_log, open_candump_log, write_candump_log};
  return format;
}

}  // namespace meter::controller
