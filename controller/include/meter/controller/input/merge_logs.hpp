// Several recorded logs (two buses logged on one clock) as one source for one replay.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "meter/controller/input/log_source.hpp"

namespace meter::controller {

// Several logs as one, pulled a frame at a time: every frame tagged with its log's input index
// (the first of each pair), the logs' frames interleaved by time: always the log whose next frame
// is earliest (ties: the earlier log). Each log's own order is kept where its timestamps tie or
// step back (a frame that steps back waits behind its log's earlier frames). The logs were
// recorded on one clock, so their relative timing is kept exactly. Holds one frame of each log.
class MergedLogSource : public LogSource {
 public:
  explicit MergedLogSource(std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs);
  // The logs merged, each with its own records (bad lines, counts).
  const std::vector<std::pair<int, std::unique_ptr<LogSource>>>& logs() const { return logs_; }
  std::size_t bad_records() const override;  // of every log

 private:
  std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs_;
  bool read_more() override;
};

}  // namespace meter::controller
