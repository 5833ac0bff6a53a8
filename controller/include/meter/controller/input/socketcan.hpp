// Live CAN bus input through a Linux raw CAN socket.
#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/controller/input/can_id_filter.hpp"
#include "meter/controller/input/input.hpp"
#include "meter/controller/input/interface_drops.hpp"

struct epoll_event;  // <sys/epoll.h>, complete where SocketCanInput is built and polled

namespace meter::controller {

class SocketCanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Live CAN bus input through raw CAN sockets: CAN FD frames enabled, kernel receive timestamps
// (SO_TIMESTAMPNS), kernel id filters (exact ids, J1939 parameter groups under a mask), every error
// class (CAN_RAW_ERR_FILTER), the kernel's drop counters (each socket's SO_RXQ_OVFL and the
// interface's rx_dropped, the frames lost before any socket), non-blocking reads driven by one
// epoll. Throws SocketCanError with a clear message when the kernel has no CAN support
// (pointing at the vcan/ VM harness) or the interface does not exist.
//
// One receive queue (socket) per id filter, like the receive mailboxes of a CAN controller: a node
// that floods one id fills only that id's queue, so the frames of every other id the mapping reads
// still arrive, and the kernel's drops land on the flooded id alone. Error frames have a queue of
// their own. Each poll drains every ready queue (at most kMaxFramesPerPoll frames from each, so
// the model keeps ticking under a flood) and hands the frames over in kernel timestamp order.
class SocketCanInput : public Input {
 public:
  // filter empty: receive everything (one queue). Otherwise only those ids (plus error frames).
  // More than CAN_RAW_FILTER_MAX (512) filters, the bound on receive queues, is a SocketCanError,
  // not a silent "all".
  SocketCanInput(const std::string& interface, const std::vector<CanIdFilter>& filter);
  ~SocketCanInput() override;
  SocketCanInput(const SocketCanInput&) = delete;
  SocketCanInput& operator=(const SocketCanInput&) = delete;
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override;
  std::string describe() const override;
  // Readable whenever any receive queue holds a frame (an epoll descriptor), for an outer epoll.
  std::optional<int> wait_fd() const override { return epoll_; }
  std::uint64_t dropped() const { return health_.kernel_drops; }  // kernel SO_RXQ_OVFL, all queues
  // Error frames (bus state), remote frames, kernel and interface drops (the interface's counter
  // read at most every kInterfaceDropsEvery), polls cut at the per-queue cap.
  static constexpr std::chrono::milliseconds kInterfaceDropsEvery{100};
  BusHealth health() const override { return health_; }
  static constexpr int kMaxFramesPerPoll = 256;  // per receive queue

 private:
  struct ReceiveQueue {
    int fd = -1;
    std::uint64_t drops = 0;  // the socket's SO_RXQ_OVFL total, as last stamped on a frame
  };
  enum class Takes { EveryFrame, OneId, ErrorFrames };  // what a receive queue's socket lets in
  void open_queue(unsigned ifindex, Takes what, const CanIdFilter* id = nullptr);
  bool drain(ReceiveQueue& queue);  // true when it stopped at the cap with frames left

  std::string iface_;
  InterfaceDrops interface_drops_;
  std::chrono::steady_clock::time_point interface_drops_due_{};  // next read of the counter
  int epoll_ = -1;
  std::vector<ReceiveQueue> queues_;
  std::vector<epoll_event> ready_;  // epoll_wait's buffer, one slot per queue
  std::vector<CanFrame> batch_;  // one poll's frames, from every ready queue
  BusHealth health_;
};

// True when socket(PF_CAN, SOCK_RAW, CAN_RAW) works on this kernel.
bool kernel_has_can();

}  // namespace meter::controller
