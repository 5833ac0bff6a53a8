// Modbus TCP / RTU client input (libmodbus).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "meter/controller/input/input.hpp"
#include "meter/controller/input/modbus_health.hpp"
#include "meter/controller/input/modbus_registers.hpp"

namespace meter::controller {

// Modbus client (libmodbus): polls the configured registers every poll period and delivers them
// as "modbus.NAME" values ("modbus.INPUT.NAME" for a named input's table). A timeout (a silent
// slave), a bad frame (CRC error), an exception response, an unreachable device or a stale
// heartbeat register makes every register invalid, exactly like a CAN timeout; each poll's outcome
// is folded into modbus_health(), which health() reports as the input's polled link. A read waits
// at most the response timeout, byte gaps inside a frame at most the same, so no poll hangs.
class ModbusInput : public Input {
 public:
  // "tcp:HOST:PORT" or "rtu:/dev/ttyX:BAUD[:8N1]".
  ModbusInput(const std::string& target, const ModbusConfig& config);
  ~ModbusInput() override;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  std::uint64_t polls() const { return health_.polls; }
  std::uint64_t failures() const { return health_.failed_polls(); }
  const std::string& last_error() const { return health_.last_error; }
  const ModbusHealth& modbus_health() const { return health_; }
  BusHealth health() const override;

 private:
  void poll_once(InputSink& sink);
  void invalidate_all(InputSink& sink, std::int64_t t);
  void fail(InputSink& sink, std::int64_t t, ModbusLinkState outcome, std::string error);
  std::string target_;
  ModbusConfig cfg_;
  void* ctx_ = nullptr;  // modbus_t*
  bool connected_ = false;
  bool serial_ = false;  // RTU: a bad or missing answer leaves the line open (flushed), not reconnected
  std::int64_t next_poll_ = 0;
  ModbusHealth health_;
  std::vector<std::string> keys_;  // per register: the key its values are delivered under
  ModbusHeartbeat heartbeat_;
  std::vector<std::array<std::uint16_t, 2>> words_;  // one poll's words, per register
  std::vector<ModbusReading> readings_;
};

}  // namespace meter::controller
