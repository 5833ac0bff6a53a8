// What a Modbus input's polls say about the link to its slave, as plain data: the state the last
// poll left it in (answering, silent, garbled, refusing, unreachable, stale) and how many polls
// failed in each way. Pure: fold poll outcomes in with note_modbus_poll(), read the result.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace meter::controller {

enum class ModbusLinkState : std::uint8_t {
  NotPolled,       // no poll yet
  Ok,              // the last poll read every register
  Unreachable,     // the device or host could not be opened or connected (no such tty, refused)
  NoResponse,      // the slave stayed silent until the response timeout (wrong unit, dead slave)
  BadFrame,        // a response arrived but was not a valid answer (CRC error, wrong length or slave)
  Exception,       // the slave answered with a Modbus exception (illegal address, device failure)
  StaleHeartbeat,  // the slave answers but its heartbeat register stopped changing
};
// "not-polled", "ok", "unreachable", "no-response", "bad-frame", "exception", "stale-heartbeat"
std::string_view to_string(ModbusLinkState state);

// What a failed libmodbus read means, by its errno: ETIMEDOUT a silent slave; a CRC, data-length,
// exception-format or wrong-slave error a bad frame; a Modbus exception code (MODBUS_ENOBASE + 1..11)
// the slave's refusal; anything else (EPIPE, ECONNRESET, EBADF, ...) an unreachable peer.
ModbusLinkState classify_modbus_read_error(int err);

struct ModbusHealth {
  ModbusLinkState state = ModbusLinkState::NotPolled;
  std::uint64_t polls = 0;
  std::uint64_t unreachable = 0, no_response = 0, bad_frames = 0, exceptions = 0, stale_heartbeats = 0;
  std::string last_error;  // the last failure's text ("read speed@0: Invalid CRC"), kept after recovery
  // Every failed poll is counted under exactly one of its kinds.
  std::uint64_t failed_polls() const { return unreachable + no_response + bad_frames + exceptions + stale_heartbeats; }
  bool operator==(const ModbusHealth&) const = default;
};

// Folds one poll's outcome in: the state becomes `outcome`, the poll and (for a failure) its
// kind counted, `error` kept as the last error.
void note_modbus_poll(ModbusHealth& health, ModbusLinkState outcome, std::string_view error = {});

// "no-response: 3 of 10 polls failed (0 unreachable, 3 no response, 0 bad frames, 0 exceptions,
// 0 stale heartbeats), last error: read a@0: Connection timed out"
std::string describe(const ModbusHealth& health);

}  // namespace meter::controller
