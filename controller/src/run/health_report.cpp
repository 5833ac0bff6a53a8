#include "health_report.hpp"

#include <cstdio>
#include <sstream>

#include "command_output.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::controller {

namespace {
constexpr std::int64_t kLossLineEveryNs = 1000000000;  // one loss line a second at most
}  // namespace

std::uint32_t view_fault_flags(const std::vector<protocol::Publisher::PeerStatus>& views) {
  std::uint32_t f = 0;
  for (const auto& v : views) f |= v.fault_flags;
  return f;
}

void HealthReport::update(const BusHealth& bus, std::uint32_t faults, std::int64_t t, std::ostream& err, Trace& trace) {
  const BusHealth& old = bus_;  // the last call's, kept until the end (assigned in place: no allocation)
  if (bus.state != old.state || (first_ && bus.state != BusState::ErrorActive)) {
    protocol::LogLine(err, bus.state == BusState::ErrorActive ? protocol::LogLevel::Info : protocol::LogLevel::Warning, "health",
                      {protocol::log_field("input", input_), protocol::log_field("bus_state", std::string(to_string(bus.state)))})
        << "meter-controller: " << input_ << ": bus " << to_string(bus.state) << " (tx/rx error counters "
        << unsigned(bus.tx_errors) << "/" << unsigned(bus.rx_errors) << ", " << bus.error_frames << " error frames)\n";
    trace.health("bus_state", static_cast<std::uint64_t>(bus.state));
  }
  if (bus.polled_links != old.polled_links) protocol::LogLine(err, protocol::LogLevel::Warning, "input", {protocol::log_field("input", input_)}) << "meter-controller: " << input_ << ": " << bus.polled_links << "\n";
  if (bus.error_frames != old.error_frames) trace.health("error_frames", bus.error_frames);
  if (bus.kernel_drops != old.kernel_drops) trace.health("kernel_drops", bus.kernel_drops);
  if (bus.interface_drops != old.interface_drops) trace.health("interface_drops", bus.interface_drops);
  if (bus.replay_slips != old.replay_slips) trace.health("replay_slips", bus.replay_slips);
  if (bus.deferred_polls != old.deferred_polls) trace.health("deferred_polls", bus.deferred_polls);
  const bool lost = bus.kernel_drops != logged_drops_ || bus.interface_drops != logged_interface_drops_ ||
                    bus.replay_slips != logged_slips_;
  if (lost && (last_loss_line_ns_ == 0 || t - last_loss_line_ns_ >= kLossLineEveryNs)) {
    protocol::LogLine(err, protocol::LogLevel::Warning, "health", {protocol::log_field("input", input_)}) << "meter-controller: " << input_ << ": frames lost: " << bus.kernel_drops - logged_drops_
        << " dropped by the kernel (receive queue full), " << bus.interface_drops - logged_interface_drops_
        << " by the interface (input backlog full), " << bus.replay_slips - logged_slips_ << " replay slips; totals "
        << bus.kernel_drops << " drops, " << bus.interface_drops << " interface drops, " << bus.replay_slips
        << " slips\n";
    logged_drops_ = bus.kernel_drops;
    logged_interface_drops_ = bus.interface_drops;
    logged_slips_ = bus.replay_slips;
    last_loss_line_ns_ = t;
  }
  if (!bus.e2e.empty()) report_e2e(bus, t, err, trace);
  if (faults != view_faults_) {
    const std::uint32_t raised = faults & ~view_faults_, cleared = view_faults_ & ~faults;
    for (int b = 0; b < 32; ++b)
      if (raised & (1U << b)) ++fault_counts_[b];
    if (raised)
      protocol::LogLine(err, protocol::LogLevel::Warning, "health", {protocol::log_field("fault", protocol::describe_fault_flags(raised))}) << "meter-controller: view reports a fault: " << protocol::describe_fault_flags(raised)
          << " (STATUS fault flags " << hex(faults) << ")\n";
    if (cleared) protocol::LogLine(err, protocol::LogLevel::Info, "health", {protocol::log_field("cleared", protocol::describe_fault_flags(cleared))}) << "meter-controller: view fault cleared: " << protocol::describe_fault_flags(cleared) << "\n";
    trace.health("view_faults", faults);
    view_faults_ = faults;
  }
  if (bus.kernel_drops != old.kernel_drops || bus.interface_drops != old.interface_drops) drop_at_ns_ = t;
  if (bus.replay_slips != old.replay_slips) slip_at_ns_ = t;
  std::uint32_t cf = 0;
  if (bus.state == BusState::ErrorWarning) cf |= protocol::kControllerFaultBusWarning;
  if (bus.state == BusState::ErrorPassive) cf |= protocol::kControllerFaultBusPassive;
  if (bus.state == BusState::BusOff) cf |= protocol::kControllerFaultBusOff;
  const std::int64_t hold = std::int64_t{protocol::kViewFaultHoldMs} * 1000000;
  if (drop_at_ns_ != 0 && t - drop_at_ns_ < hold) cf |= protocol::kControllerFaultFramesLost;
  if (slip_at_ns_ != 0 && t - slip_at_ns_ < hold) cf |= protocol::kControllerFaultReplaySlip;
  controller_faults_ = cf;
  first_ = false;
  bus_ = bus;
}

void HealthReport::report_e2e(const BusHealth& bus, std::int64_t t, std::ostream& err, Trace& trace) {
  logged_refused_.resize(bus.e2e.size(), 0);
  mismatch_logged_.resize(bus.e2e.size(), false);
  std::uint64_t refused = 0, before = 0;
  for (std::size_t i = 0; i < bus.e2e.size(); ++i) refused += bus.e2e[i].refused, before += logged_refused_[i];
  if (refused != before && (last_e2e_line_ns_ == 0 || t - last_e2e_line_ns_ >= kLossLineEveryNs)) {
    std::ostringstream line;
    line << "meter-controller: " << input_ << ": e2e: " << refused - before << " frame(s) refused (not used:";
    for (std::size_t i = 0; i < bus.e2e.size(); ++i) {
      const E2eHealth& m = bus.e2e[i];
      if (m.refused != logged_refused_[i]) line << " " << m.message << " " << m.refused - logged_refused_[i];
      logged_refused_[i] = m.refused;
    }
    line << "); totals: ";
    for (std::size_t i = 0; i < bus.e2e.size(); ++i)
      if (bus.e2e[i].refused) line << describe(bus.e2e[i]) << (i + 1 < bus.e2e.size() ? ", " : "");
    protocol::LogLine(err, protocol::LogLevel::Warning, "e2e",
                      {protocol::log_field("input", input_), protocol::log_field("refused", static_cast<std::int64_t>(refused - before))})
        << line.str();
    trace.health("e2e_refused", refused);
    last_e2e_line_ns_ = t;
  }
  for (std::size_t i = 0; i < bus.e2e.size(); ++i) {
    const E2eHealth& m = bus.e2e[i];
    if (m.mismatch && !mismatch_logged_[i])
      protocol::LogLine(err, protocol::LogLevel::Error, "e2e", {protocol::log_field("input", input_), protocol::log_field("can_message", m.message)})
          << "meter-controller: " << input_ << ": e2e: " << m.message << ": likely configuration mismatch: " << m.refused
          << " of " << m.checked << " frames refused (" << m.checksum << " checksum, " << m.repeated << " repeated, "
          << m.out_of_sequence << " out of sequence); its signals time out as if it were silent: check its [e2e "
          << m.message << "] section, the make and the DBC ('meter-controller decode --e2e' on a recorded log)\n";
    mismatch_logged_[i] = m.mismatch;
  }
}

std::uint64_t HealthReport::view_fault_count(std::uint32_t fault) const {
  for (int b = 0; b < 32; ++b)
    if (fault == (1U << b)) return fault_counts_[b];
  return 0;
}

std::string HealthReport::stats_text() const {
  std::string s = "bus " + describe(bus_) + ", view faults: ";
  std::string seen;
  for (int b = 0; b < 32; ++b) {
    if (!fault_counts_[b]) continue;
    if (!seen.empty()) seen += ", ";
    seen += protocol::describe_fault_flags(1U << b) + " " + std::to_string(fault_counts_[b]);
  }
  return s + (seen.empty() ? "none" : seen);
}

}  // namespace meter::controller
