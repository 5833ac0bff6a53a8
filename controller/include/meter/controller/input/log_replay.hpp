// Replays a recorded log as an input: in recorded time, scaled, or on a simulated clock (fast). The
// frames are pulled from a LogSource as they fall due, so only the source's window is held.
// When the log has ended the input is a silent bus: its clock runs on (in wall time, scaled as
// before; a fast replay's simulated clock continues at wall rate) and poll() waits its timeout and
// reports the end, so a controller that stays up sees its values time out.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/input.hpp"

namespace meter::controller {

enum class ReplayMode { Fast, Realtime, Scaled };
struct ReplayOptions {
  ReplayMode mode = ReplayMode::Realtime;
  double scale = 1.0;  // Scaled: log seconds per wall second (2 = twice as fast)
  // Fast mode: simulated time advanced per poll() (frames up to now + step are delivered).
  std::chrono::milliseconds fast_step{10};
};
// Parses "realtime", "fast", "scale:N".
ReplayOptions parse_replay(std::string_view text);  // throws std::invalid_argument

class LogReplay : public Input {
 public:
  LogReplay(std::unique_ptr<LogSource> log, ReplayOptions options);
  LogReplay(ParsedLog log, ReplayOptions options);  // frames already in memory
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  double rate() const override { return opt_.mode == ReplayMode::Scaled ? opt_.scale : 1.0; }
  const LogSource& source() const { return *log_; }
  std::size_t delivered() const { return delivered_; }
  std::size_t slips() const { return slips_; }  // times the replay clock slipped (we fell behind)
  BusHealth health() const override;  // error frames in the log, and the slips
  static constexpr std::int64_t kMaxLagNs = 20000000;  // 20 ms of log time

 private:
  std::unique_ptr<LogSource> log_;
  const CanFrame* next_ = nullptr;  // the next frame to deliver (held by the source); nullptr: the log's end
  ReplayOptions opt_;
  std::size_t delivered_ = 0;
  std::int64_t sim_now_ = 0;        // fast mode clock
  std::int64_t log_start_ = 0;      // first frame's timestamp
  std::int64_t wall_start_ = 0;     // CLOCK_MONOTONIC at the first poll (realtime / scaled)
  bool begun_ = false;
  bool ended_ = false;              // every frame delivered: from now on a silent bus
  std::size_t slips_ = 0;
  BusHealth bus_;
  void deliver(InputSink& sink);
  bool mark_end();                  // true (and remembers when) once every frame is delivered
};

}  // namespace meter::controller
