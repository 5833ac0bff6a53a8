// Several recorded logs merged onto one timeline.
#include "meter/controller/input/merge_logs.hpp"

namespace meter::controller {

ParsedLog merge_logs(std::vector<std::pair<int, ParsedLog>> logs) {
  ParsedLog out;
  std::size_t total = 0;
  if (!logs.empty()) out.format = logs.front().second.format;
  for (auto& [index, log] : logs) {
    total += log.frames.size();
    out.lines += log.lines;
    for (BadLine& b : log.bad_lines) out.bad_lines.push_back(std::move(b));
    for (CanFrame& f : log.frames) f.input = static_cast<std::uint8_t>(index);
  }
  out.frames.reserve(total);
  // k-way merge: always the log whose next frame is earliest (ties: the earlier --input).
  std::vector<std::size_t> next(logs.size(), 0);
  while (out.frames.size() < total) {
    std::size_t best = logs.size();
    for (std::size_t i = 0; i < logs.size(); ++i) {
      const auto& frames = logs[i].second.frames;
      if (next[i] == frames.size()) continue;
      if (best == logs.size() || frames[next[i]].timestamp_ns < logs[best].second.frames[next[best]].timestamp_ns) best = i;
    }
    out.frames.push_back(logs[best].second.frames[next[best]++]);
  }
  return out;
}

}  // namespace meter::controller
