// Live CAN bus input through a Linux raw CAN socket.
#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/controller/input/input.hpp"

namespace meter::controller {

// One identifier the kernel filter lets through.
struct CanIdFilter {
  std::uint32_t id = 0;
  bool extended = false;
  friend bool operator==(const CanIdFilter&, const CanIdFilter&) = default;
};

class SocketCanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Raw CAN socket with CAN FD frames enabled, kernel receive timestamps (SO_TIMESTAMPNS), kernel id
// filters, non-blocking reads driven by epoll. Throws SocketCanError with a clear message when the
// kernel has no CAN support (pointing at the vcan/ VM harness) or the interface does not exist.
class SocketCanInput : public Input {
 public:
  // filter empty: receive everything. Otherwise only those ids (plus error frames).
  SocketCanInput(const std::string& interface, const std::vector<CanIdFilter>& filter);
  ~SocketCanInput() override;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  int fd() const { return fd_; }
  std::uint64_t dropped() const { return dropped_; }  // kernel SO_RXQ_OVFL count

 private:
  std::string iface_;
  int fd_ = -1, epoll_ = -1;
  std::uint64_t dropped_ = 0;
};

// True when socket(PF_CAN, SOCK_RAW, CAN_RAW) works on this kernel.
bool kernel_has_can();

}  // namespace meter::controller
