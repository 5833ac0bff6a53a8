// Live CAN bus input through a Linux raw CAN socket.
#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/controller/input/can_id_filter.hpp"
#include "meter/controller/input/input.hpp"

namespace meter::controller {

class SocketCanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Raw CAN socket with CAN FD frames enabled, kernel receive timestamps (SO_TIMESTAMPNS), kernel id
// filters (exact ids, J1939 parameter groups under a mask), every error class (CAN_RAW_ERR_FILTER),
// the kernel's drop counter (SO_RXQ_OVFL), non-blocking reads driven by epoll. Throws SocketCanError with a clear message when the
// kernel has no CAN support (pointing at the vcan/ VM harness) or the interface does not exist.
class SocketCanInput : public Input {
 public:
  // filter empty: receive everything. Otherwise only those ids (plus error frames). More filters
  // than the kernel takes (CAN_RAW_FILTER_MAX, 512) is a SocketCanError, not a silent "all".
  SocketCanInput(const std::string& interface, const std::vector<CanIdFilter>& filter);
  ~SocketCanInput() override;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  int fd() const { return fd_; }
  std::uint64_t dropped() const { return health_.kernel_drops; }  // kernel SO_RXQ_OVFL count
  // Error frames (bus state), remote frames, kernel drops, polls cut at the per-poll cap.
  BusHealth health() const override { return health_; }
  static constexpr int kMaxFramesPerPoll = 256;

 private:
  std::string iface_;
  int fd_ = -1, epoll_ = -1;
  BusHealth health_;
};

// True when socket(PF_CAN, SOCK_RAW, CAN_RAW) works on this kernel.
bool kernel_has_can();

}  // namespace meter::controller
