// What a CAN bus says about itself, as plain data: the controller state its error frames report
// (error-active, warning, error-passive, bus-off), the error classes seen, and the counts an input
// keeps of frames it could not deliver (kernel receive-queue drops, replay slips). Pure: fold
// frames in with note_frame(), read the result; no socket, no clock.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {

// ISO 11898-1 fault confinement, as Linux CAN drivers report it in error frames.
enum class BusState : std::uint8_t { ErrorActive, ErrorWarning, ErrorPassive, BusOff };
std::string_view to_string(BusState state);  // "error-active", "error-warning", "error-passive", "bus-off"

// One protected message's end-to-end checks (e2e/e2e_guard.hpp), filled in by the run loop from
// the model, not by frames: a refused frame is one the bus delivered but the model did not use.
struct E2eHealth {
  std::string message;
  std::uint64_t checked = 0, refused = 0;
  std::uint64_t checksum = 0;         // bad checksum (or a frame too short to hold it)
  std::uint64_t repeated = 0;         // the counter did not move: a stale sender, or a replay
  std::uint64_t out_of_sequence = 0;  // the counter jumped past its tolerance (and the frames resynchronising)
  std::uint64_t lost = 0;             // frames a tolerated counter jump says were lost
  bool mismatch = false;              // nearly every frame refused: likely a configuration mismatch
  bool operator==(const E2eHealth&) const = default;
};

struct BusHealth {
  BusState state = BusState::ErrorActive;
  std::uint64_t error_frames = 0;
  std::uint64_t remote_frames = 0;       // RTR: carry no data, never decoded
  std::uint64_t bus_off_events = 0;      // times the controller went bus-off
  std::uint64_t restarts = 0;            // CAN_ERR_RESTARTED: back from bus-off
  std::uint64_t protocol_errors = 0;     // CAN_ERR_PROT / CAN_ERR_BUSERROR frames
  std::uint64_t no_ack = 0;              // CAN_ERR_ACK: nobody acknowledged (alone on the bus)
  std::uint64_t controller_overflows = 0;  // CAN_ERR_CRTL RX/TX overflow in the CAN controller
  std::uint8_t tx_errors = 0, rx_errors = 0;  // last error counters reported (CAN_ERR_CNT)
  // Input-side losses, filled by the input (not by frames): every frame the bus carried on a mapped
  // id either reached the model or is counted here (interface drops count every id's losses, mapped
  // or not, since the interface drops them before any filter).
  std::uint64_t kernel_drops = 0;   // SO_RXQ_OVFL: the socket's receive queue overflowed
  std::uint64_t interface_drops = 0;  // the interface's rx_dropped: lost before any socket
  std::uint64_t replay_slips = 0;   // a replay fell more than its lag bound behind the log clock
  std::uint64_t deferred_polls = 0;  // polls that stopped at the per-poll cap with frames still queued
  // A polled input's (Modbus) link to its slave, as its last poll left it: "Modbus rtu:/dev/ttyUSB0:19200
  // no-response (read speed@0: Connection timed out)", or "... ok"; several joined by "; ". Empty for
  // a CAN bus or a log.
  std::string polled_links;
  std::vector<E2eHealth> e2e;        // per protected message; empty when nothing is protected
  bool operator==(const BusHealth&) const = default;
};

// Folds one received frame into health: error frames update the state and the class counts,
// remote frames are counted; data frames change nothing.
void note_frame(BusHealth& health, const CanFrame& frame);

// Folds another bus's health into total: the worse of the two states, every count summed, the
// larger error counters, the E2E counts of a message summed (by name).
void add_health(BusHealth& total, const BusHealth& other);

// "error-passive, 3 error frames (1 bus-off), tx/rx errors 128/0, 0 kernel drops, 0 interface
// drops, 0 replay slips", then, with protected messages, "; e2e: Steering 3 of 100 refused (...)"
std::string describe(const BusHealth& health);
// "Steering 3 of 100 refused (3 checksum, 0 repeated, 0 out of sequence; 0 lost)"
std::string describe(const E2eHealth& message);

}  // namespace meter::controller
