// Modbus TCP / RTU client input (libmodbus).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "meter/controller/input/input.hpp"
#include "meter/controller/input/modbus_registers.hpp"

namespace meter::controller {

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
  ModbusHeartbeat heartbeat_;
  std::vector<std::array<std::uint16_t, 2>> words_;  // one poll's words, per register
  std::vector<ModbusReading> readings_;
};

}  // namespace meter::controller
