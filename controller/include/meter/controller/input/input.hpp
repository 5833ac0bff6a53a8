// Input backends behind one small interface. Each backend delivers CAN frames (or, for Modbus,
// named register values) to a Sink, and tells the time on its own clock: the log's time for a
// replayed log (simulated in fast mode, so tests are deterministic), the wall clock for live buses.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "meter/controller/input/bus_health.hpp"
#include "meter/controller/input/can_frame.hpp"

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
  // What to wait on before the next poll: a file descriptor that turns readable when the input has
  // frames to deliver (a SocketCAN bus), or none for an input that paces itself (a replayed log,
  // the Modbus poll period), which the caller polls without waiting at each wake-up.
  virtual std::optional<int> wait_fd() const { return std::nullopt; }
  // Input-clock seconds per wall second (a scaled replay runs faster; live inputs are 1).
  virtual double rate() const { return 1.0; }
  // The bus's state as its error frames tell it, and the frames this input could not deliver
  // (kernel drops, replay slips); inputs without a CAN bus report nothing.
  virtual BusHealth health() const { return {}; }
};

}  // namespace meter::controller
