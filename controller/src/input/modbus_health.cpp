#include "meter/controller/input/modbus_health.hpp"

#include <modbus.h>

#include <cerrno>

namespace meter::controller {

std::string_view to_string(ModbusLinkState state) {
  switch (state) {
    case ModbusLinkState::NotPolled: return "not-polled";
    case ModbusLinkState::Ok: return "ok";
    case ModbusLinkState::Unreachable: return "unreachable";
    case ModbusLinkState::NoResponse: return "no-response";
    case ModbusLinkState::BadFrame: return "bad-frame";
    case ModbusLinkState::Exception: return "exception";
    case ModbusLinkState::StaleHeartbeat: return "stale-heartbeat";
  }
  return "?";
}

ModbusLinkState classify_modbus_read_error(int err) {
  if (err == ETIMEDOUT) return ModbusLinkState::NoResponse;
  if (err == EMBBADCRC || err == EMBBADDATA || err == EMBBADEXC || err == EMBMDATA || err == EMBBADSLAVE || err == EMBUNKEXC)
    return ModbusLinkState::BadFrame;
  if (err > MODBUS_ENOBASE && err <= EMBXGTAR) return ModbusLinkState::Exception;
  return ModbusLinkState::Unreachable;
}

void note_modbus_poll(ModbusHealth& h, ModbusLinkState outcome, std::string_view error) {
  ++h.polls;
  h.state = outcome;
  switch (outcome) {
    case ModbusLinkState::NotPolled:
    case ModbusLinkState::Ok: return;
    case ModbusLinkState::Unreachable: ++h.unreachable; break;
    case ModbusLinkState::NoResponse: ++h.no_response; break;
    case ModbusLinkState::BadFrame: ++h.bad_frames; break;
    case ModbusLinkState::Exception: ++h.exceptions; break;
    case ModbusLinkState::StaleHeartbeat: ++h.stale_heartbeats; break;
  }
  h.last_error = std::string(error);
}

std::string describe(const ModbusHealth& h) {
  std::string s = std::string(to_string(h.state)) + ": " + std::to_string(h.failed_polls()) + " of " + std::to_string(h.polls) +
                  " polls failed (" + std::to_string(h.unreachable) + " unreachable, " + std::to_string(h.no_response) +
                  " no response, " + std::to_string(h.bad_frames) + " bad frames, " + std::to_string(h.exceptions) +
                  " exceptions, " + std::to_string(h.stale_heartbeats) + " stale heartbeats)";
  if (!h.last_error.empty()) s += ", last error: " + h.last_error;
  return s;
}

}  // namespace meter::controller
