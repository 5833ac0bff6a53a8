// Error frames as Linux CAN drivers write them (linux/can/error.h): the class bits in the id,
// the controller state in data[1], the error counters in data[6]/data[7].
#include "meter/controller/input/bus_health.hpp"

#include <algorithm>

#include <linux/can/error.h>

namespace meter::controller {

std::string_view to_string(BusState s) {
  switch (s) {
    case BusState::ErrorActive: return "error-active";
    case BusState::ErrorWarning: return "error-warning";
    case BusState::ErrorPassive: return "error-passive";
    case BusState::BusOff: return "bus-off";
  }
  return "unknown";
}

void note_frame(BusHealth& h, const CanFrame& f) {
  if (f.rtr && !f.error) {
    ++h.remote_frames;
    return;
  }
  if (!f.error) return;
  ++h.error_frames;
  const std::uint32_t cls = f.id;
  const auto byte = [&](std::size_t i) -> std::uint8_t { return i < f.len ? f.data[i] : 0; };
  if (cls & CAN_ERR_CNT) {
    h.tx_errors = byte(6);
    h.rx_errors = byte(7);
  }
  if (cls & CAN_ERR_CRTL) {
    const std::uint8_t c = byte(1);
    if (c & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) ++h.controller_overflows;
    if (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE))
      h.state = BusState::ErrorPassive;
    else if (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING))
      h.state = BusState::ErrorWarning;
    else if (c & CAN_ERR_CRTL_ACTIVE)
      h.state = BusState::ErrorActive;
  }
  if (cls & (CAN_ERR_PROT | CAN_ERR_BUSERROR)) ++h.protocol_errors;
  if (cls & CAN_ERR_ACK) ++h.no_ack;
  if (cls & CAN_ERR_RESTARTED) {
    ++h.restarts;
    h.state = BusState::ErrorActive;
  }
  if (cls & CAN_ERR_BUSOFF) {  // last: bus-off outranks any state the same frame reports
    if (h.state != BusState::BusOff) ++h.bus_off_events;
    h.state = BusState::BusOff;
  }
}

void add_health(BusHealth& total, const BusHealth& other) {
  total.state = std::max(total.state, other.state);  // the enum runs from healthy to bus-off
  total.error_frames += other.error_frames;
  total.remote_frames += other.remote_frames;
  total.bus_off_events += other.bus_off_events;
  total.restarts += other.restarts;
  total.protocol_errors += other.protocol_errors;
  total.no_ack += other.no_ack;
  total.controller_overflows += other.controller_overflows;
  total.tx_errors = std::max(total.tx_errors, other.tx_errors);
  total.rx_errors = std::max(total.rx_errors, other.rx_errors);
  total.kernel_drops += other.kernel_drops;
  total.interface_drops += other.interface_drops;
  total.replay_slips += other.replay_slips;
  total.deferred_polls += other.deferred_polls;
  if (!other.polled_links.empty()) total.polled_links += (total.polled_links.empty() ? "" : "; ") + other.polled_links;
  for (const E2eHealth& m : other.e2e) {
    auto it = std::find_if(total.e2e.begin(), total.e2e.end(), [&](const E2eHealth& t) { return t.message == m.message; });
    if (it == total.e2e.end()) {
      total.e2e.push_back(m);
      continue;
    }
    it->checked += m.checked, it->refused += m.refused, it->checksum += m.checksum, it->repeated += m.repeated;
    it->out_of_sequence += m.out_of_sequence, it->lost += m.lost, it->mismatch = it->mismatch || m.mismatch;
  }
}

std::string describe(const E2eHealth& m) {
  std::string s = m.message + " " + std::to_string(m.refused) + " of " + std::to_string(m.checked) + " refused (" +
                  std::to_string(m.checksum) + " checksum, " + std::to_string(m.repeated) + " repeated, " +
                  std::to_string(m.out_of_sequence) + " out of sequence; " + std::to_string(m.lost) + " lost)";
  if (m.mismatch) s += " LIKELY CONFIGURATION MISMATCH";
  return s;
}

std::string describe(const BusHealth& h) {
  std::string s(to_string(h.state));
  s += ", " + std::to_string(h.error_frames) + " error frames (" + std::to_string(h.bus_off_events) + " bus-off, " +
       std::to_string(h.protocol_errors) + " protocol, " + std::to_string(h.no_ack) + " no-ack), tx/rx errors " +
       std::to_string(h.tx_errors) + "/" + std::to_string(h.rx_errors) + ", " + std::to_string(h.remote_frames) +
       " remote frames, " + std::to_string(h.kernel_drops) + " kernel drops, " + std::to_string(h.interface_drops) +
       " interface drops, " + std::to_string(h.replay_slips) +
       " replay slips, " + std::to_string(h.deferred_polls) + " deferred polls";
  if (!h.polled_links.empty()) s += ", " + h.polled_links;
  for (std::size_t i = 0; i < h.e2e.size(); ++i) s += (i == 0 ? "; e2e: " : ", ") + describe(h.e2e[i]);
  return s;
}

}  // namespace meter::controller
