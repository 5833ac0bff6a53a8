// What the run loop tells about the health of its bus and of its views: a log line when the bus
// state changes, when frames are lost (kernel drops, replay slips; at most one line a second),
// when protected messages' frames are refused by their E2E checks (at most one line a second) and
// once when a message looks misconfigured (nearly every frame refused),
// when a view reports a fault in its STATUS or the fault clears; the --trace 'h' rows; and the
// health part of the final stats line.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "latency_trace.hpp"
#include "meter/controller/input/bus_health.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::controller {

// The fault flags of every connected view, ORed.
std::uint32_t view_fault_flags(const std::vector<protocol::Publisher::PeerStatus>& views);

class HealthReport {
 public:
  explicit HealthReport(std::string input_name) : input_(std::move(input_name)) {}
  // Compares with the previous call; t_ns is the input's clock (rate-limits the loss lines).
  void update(const BusHealth& bus, std::uint32_t view_faults, std::int64_t t_ns, std::ostream& err, Trace& trace);
  // "bus error-active, 0 error frames (...), 0 kernel drops, ..., view faults: dump-failed 1"
  std::string stats_text() const;
  const BusHealth& bus() const { return bus_; }
  // The controller's faults for its STATUS to the views (protocol kControllerFault*): the bus
  // state, and frames lost / a replay slip within the last second of input time.
  std::uint32_t controller_faults() const { return controller_faults_; }
  // Times each view fault bit was raised (its rising edges in the STATUS flags).
  std::uint64_t view_fault_count(std::uint32_t fault) const;

 private:
  std::string input_;
  BusHealth bus_;
  bool first_ = true;
  std::uint64_t logged_drops_ = 0, logged_interface_drops_ = 0, logged_slips_ = 0;
  std::int64_t last_loss_line_ns_ = 0;
  std::vector<std::uint64_t> logged_refused_;  // per protected message, as of the last E2E line
  std::vector<bool> mismatch_logged_;
  std::int64_t last_e2e_line_ns_ = 0;
  std::uint32_t view_faults_ = 0;
  std::uint32_t controller_faults_ = 0;
  std::int64_t drop_at_ns_ = 0, slip_at_ns_ = 0;  // input time of the last loss, 0 = none
  std::uint64_t fault_counts_[32] = {};
  void report_e2e(const BusHealth& bus, std::int64_t t_ns, std::ostream& err, Trace& trace);
};

}  // namespace meter::controller
