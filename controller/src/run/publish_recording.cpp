#include "publish_recording.hpp"

#include <stdexcept>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/recording.hpp"

namespace meter::controller {

PublishRecording::PublishRecording(const std::string& path) : path_(path) {
  if (path.empty()) return;
  out_.open(path);
  if (!out_) throw std::runtime_error(path + ": cannot write the recording (--record)");
  out_ << protocol::recording_header(protocol::catalog_hash()) << "\n";
}

void PublishRecording::write(std::int64_t t_ns, protocol::Message message) {
  protocol::RecordedFrame r;
  r.received_ns = t_ns;
  r.frame.sequence = ++sequence_;
  r.frame.timestamp_ns = t_ns;
  r.frame.message = std::move(message);
  out_ << protocol::format_line(r) << "\n";
}

void PublishRecording::snapshot(std::int64_t t_ns, std::vector<protocol::SignalUpdate> all) {
  if (on()) write(t_ns, protocol::Snapshot{true, std::move(all)});
}

void PublishRecording::delta(std::int64_t t_ns, std::vector<protocol::SignalUpdate> changed) {
  if (on() && !changed.empty()) write(t_ns, protocol::Delta{std::move(changed)});
}

void PublishRecording::status(std::int64_t t_ns, std::uint64_t frames_received, std::uint64_t frames_lost,
                              std::uint32_t fault_flags) {
  if (!on() || (status_written_ && fault_flags == last_faults_)) return;
  status_written_ = true;
  last_faults_ = fault_flags;
  write(t_ns, protocol::Status{frames_received, frames_lost, fault_flags});
}

void PublishRecording::close() {
  if (!on()) return;
  out_.flush();
  if (!out_) throw std::runtime_error(path_ + ": write error on the recording (--record)");
  out_.close();
}

}  // namespace meter::controller
