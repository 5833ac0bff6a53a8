// Input backends behind one small interface. Each backend delivers CAN frames (or, for Modbus,
// named register values) to a Sink, and tells the time on its own clock: the log's time for a
// replayed log (simulated in fast mode, so tests are deterministic), the wall clock for live buses.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/can_frame.hpp"
#include "meter/controller/mapping.hpp"

namespace meter::controller {

class InputSink {
 public:
  virtual ~InputSink() = default;
  virtual void on_frame(const CanFrame& frame) = 0;
  virtual void on_value(std::string_view key, double value, bool valid, std::int64_t t_ns) = 0;
};

class Input {
 public:
  virtual ~Input() = default;
  // Delivers what is available, waiting at most 'timeout' (on the input's clock, scaled for a
  // replay). Returns false once the input has ended (end of log); live inputs never end.
  virtual bool poll(InputSink& sink, std::chrono::milliseconds timeout) = 0;
  virtual std::int64_t now_ns() const = 0;  // current time on this input's clock
  virtual std::string describe() const = 0;
  // Input-clock seconds per wall second (a scaled replay runs faster; live inputs are 1).
  virtual double rate() const { return 1.0; }
};

// ---------------------------------------------------------------- candump -L logs

struct BadLine {
  std::size_t line;
  std::string why;
};

struct ParsedLog {
  std::vector<CanFrame> frames;
  std::vector<BadLine> bad_lines;  // skipped, with their line numbers
  std::size_t lines = 0;
};
ParsedLog parse_candump_log(std::string_view text);
ParsedLog load_candump_log(const std::string& path);  // throws std::runtime_error if unreadable

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
  LogReplay(ParsedLog log, ReplayOptions options);
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  double rate() const override { return opt_.mode == ReplayMode::Scaled ? opt_.scale : 1.0; }
  const ParsedLog& log() const { return log_; }
  std::size_t delivered() const { return next_; }
  std::size_t slips() const { return slips_; }  // times the replay clock slipped (we fell behind)
  static constexpr std::int64_t kMaxLagNs = 20000000;  // 20 ms of log time

 private:
  ParsedLog log_;
  ReplayOptions opt_;
  std::size_t next_ = 0;
  std::int64_t sim_now_ = 0;        // fast mode clock
  std::int64_t log_start_ = 0;      // first frame's timestamp
  std::int64_t wall_start_ = 0;     // CLOCK_MONOTONIC at the first poll (realtime / scaled)
  bool begun_ = false;
  std::size_t slips_ = 0;
};

// ---------------------------------------------------------------- SocketCAN

class SocketCanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Raw CAN socket with CAN FD frames enabled, kernel receive timestamps (SO_TIMESTAMPNS), kernel id
// filters, non-blocking reads driven by epoll. Throws SocketCanError with a clear message when the
// kernel has no CAN support (pointing at the vcan/ VM harness) or the interface does not exist.
class SocketCanInput : public Input {
 public:
  // filter_ids empty: receive everything. Otherwise only those ids (plus error frames).
  SocketCanInput(const std::string& interface, const std::vector<std::pair<std::uint32_t, bool>>& filter_ids);
  ~SocketCanInput() override;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  int fd() const { return fd_; }
  std::uint64_t dropped() const { return dropped_; }  // kernel SO_RXQ_OVFL count

 private:
  std::string iface_;
  int fd_ = -1, epoll_ = -1;
  std::uint64_t dropped_ = 0;
};

// True when socket(PF_CAN, SOCK_RAW, CAN_RAW) works on this kernel.
bool kernel_has_can();

// ---------------------------------------------------------------- Modbus

// Modbus client (libmodbus): polls the configured registers every poll period and delivers them
// as "modbus.NAME" values. A timeout, an exception response or a stale heartbeat register makes
// every register invalid, exactly like a CAN timeout.
class ModbusInput : public Input {
 public:
  // "tcp:HOST:PORT" or "rtu:/dev/ttyX:BAUD[:8N1]".
  ModbusInput(const std::string& target, const ModbusConfig& config);
  ~ModbusInput() override;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  std::uint64_t polls() const { return polls_; }
  std::uint64_t failures() const { return failures_; }
  const std::string& last_error() const { return last_error_; }

 private:
  void poll_once(InputSink& sink);
  void invalidate_all(InputSink& sink, std::int64_t t);
  std::string target_;
  ModbusConfig cfg_;
  void* ctx_ = nullptr;  // modbus_t*
  bool connected_ = false;
  std::int64_t next_poll_ = 0;
  std::uint64_t polls_ = 0, failures_ = 0;
  std::string last_error_;
  int hb_same_ = 0;
  bool hb_seen_ = false;
  std::uint16_t hb_last_[2] = {0, 0};
};

}  // namespace meter::controller
