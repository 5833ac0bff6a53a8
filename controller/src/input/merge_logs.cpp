// Several recorded logs merged onto one timeline, a frame at a time.
#include "meter/controller/input/merge_logs.hpp"

namespace meter::controller {

MergedLogSource::MergedLogSource(std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs) : logs_(std::move(logs)) {
  if (!logs_.empty()) window().format = logs_.front().second->records().format;
}

bool MergedLogSource::read_more() {
  // k-way merge: always the log whose next frame is earliest (ties: the earlier --input).
  const CanFrame* best = nullptr;
  int best_index = 0;
  LogSource* from = nullptr;
  for (auto& [index, log] : logs_) {
    const CanFrame* f = log->peek();
    if (f && (!best || f->timestamp_ns < best->timestamp_ns)) {
      best = f;
      best_index = index;
      from = log.get();
    }
  }
  if (!best) return false;
  CanFrame f = *from->next();
  f.input = static_cast<std::uint8_t>(best_index);
  window().frames.push_back(f);
  return true;
}

std::size_t MergedLogSource::bad_records() const {
  std::size_t n = 0;
  for (const auto& [index, log] : logs_) n += log->bad_records();
  return n;
}

}  // namespace meter::controller
