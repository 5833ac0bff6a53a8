#include <time.h>

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "meter/controller/input/clocks.hpp"
#include "meter/controller/input/log_replay.hpp"

namespace meter::controller {
ReplayOptions parse_replay(std::string_view text) {
  ReplayOptions o;
  if (text == "realtime") {
    o.mode = ReplayMode::Realtime;
  } else if (text == "fast") {
    o.mode = ReplayMode::Fast;
  } else if (text.rfind("scale:", 0) == 0) {
    std::string v(text.substr(6));
    char* end = nullptr;
    double s = std::strtod(v.c_str(), &end);
    if (v.empty() || end != v.c_str() + v.size() || !(s > 0) || !std::isfinite(s))
      throw std::invalid_argument("--replay scale:N: expected a factor > 0, got '" + v + "'");
    o.mode = ReplayMode::Scaled;
    o.scale = s;
  } else {
    throw std::invalid_argument("--replay: expected realtime, fast or scale:N, got '" + std::string(text) + "'");
  }
  return o;
}

LogReplay::LogReplay(std::unique_ptr<LogSource> log, ReplayOptions options) : log_(std::move(log)), opt_(options) {
  if (opt_.mode == ReplayMode::Realtime) opt_.scale = 1.0;
  next_ = log_->next();
  if (next_) {
    log_start_ = next_->timestamp_ns;
    sim_now_ = log_start_;
  }
}

LogReplay::LogReplay(ParsedLog log, ReplayOptions options) : LogReplay(std::make_unique<ParsedLogSource>(std::move(log)), options) {}

std::int64_t LogReplay::now_ns() const {
  if (opt_.mode == ReplayMode::Fast || !begun_) return sim_now_;
  return log_start_ + static_cast<std::int64_t>(static_cast<double>(monotonic_ns() - wall_start_) * opt_.scale);
}

bool LogReplay::poll(InputSink& sink, std::chrono::milliseconds timeout) {
  if (!begun_) {
    begun_ = true;
    wall_start_ = monotonic_ns();
  }
  if (ended_) {
    // The log is over: the bus stays silent. Wait as a live input with nothing to read would.
    const auto wall = static_cast<std::int64_t>(static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count()) / rate());
    if (wall > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wall));
    // The simulated clock runs on by each wait (at wall rate, as the wait sleeps that long): a
    // silent bus on which timeouts expire, its time never depending on how busy the machine is.
    if (opt_.mode == ReplayMode::Fast) sim_now_ += std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
    return false;
  }
  if (opt_.mode == ReplayMode::Fast) {
    // Simulated clock: advance one step and hand over everything due by then. No sleeping.
    sim_now_ += std::chrono::duration_cast<std::chrono::nanoseconds>(opt_.fast_step).count();
    while (next_ && next_->timestamp_ns <= sim_now_) deliver(sink);
    return !mark_end();
  }
  // Realtime / scaled: frames are handed over in batches at the caller's poll cadence (the model
  // ticks at that cadence anyway), so the process wakes ~100 times a second, not once per frame.
  const std::int64_t timeout_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
  const std::int64_t deadline = monotonic_ns() + timeout_ns;
  std::int64_t now = now_ns();
  if (next_ && next_->timestamp_ns > now) {
    const auto due_wall = static_cast<std::int64_t>(static_cast<double>(next_->timestamp_ns - now) / opt_.scale);
    const std::int64_t wait = std::min(deadline - monotonic_ns(), due_wall);
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    if (monotonic_ns() < deadline) {
      const std::int64_t rest = deadline - monotonic_ns();
      if (rest > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(rest));
    }
    now = now_ns();
  }
  // Fell behind by more than one batch (descheduled, a slow disk): let the replay clock slip
  // instead of handing over a burst of stale frames, as canplayer does. Gaps stay as recorded.
  const std::int64_t allowed = kMaxLagNs + static_cast<std::int64_t>(static_cast<double>(timeout_ns) * opt_.scale);
  if (next_ && now - next_->timestamp_ns > allowed) {
    const std::int64_t behind = now - next_->timestamp_ns;
    wall_start_ += static_cast<std::int64_t>(static_cast<double>(behind) / opt_.scale);
    now -= behind;
    ++slips_;
  }
  while (next_ && next_->timestamp_ns <= now) deliver(sink);
  return !mark_end();
}

bool LogReplay::mark_end() {
  if (next_) return false;
  ended_ = true;
  return true;
}

void LogReplay::deliver(InputSink& sink) {
  note_frame(bus_, *next_);
  sink.on_frame(*next_);  // held by the source until the next frame is asked for
  ++delivered_;
  next_ = log_->next();
}

BusHealth LogReplay::health() const {
  BusHealth h = bus_;
  h.replay_slips = slips_;
  return h;
}

std::string LogReplay::describe() const {
  std::string mode = opt_.mode == ReplayMode::Fast ? "fast" : opt_.mode == ReplayMode::Realtime ? "realtime" : "scale:" + std::to_string(opt_.scale);
  // Streamed: how many frames the log holds is known only once it has been replayed.
  return std::string(log_->records().format) + " log (streamed, replay " + mode + ")";
}

}  // namespace meter::controller
