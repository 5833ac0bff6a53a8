// SocketCAN raw socket input. The build machine's kernel has no CAN; this path runs inside the
// vcan/ VM harness (docs/vcan.md), where vcan0 exists.
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "meter/controller/input/clocks.hpp"
#include "meter/controller/input/socketcan.hpp"

namespace meter::controller {

namespace {
std::string no_can_message(int err) {
  return std::string("socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: ") + std::strerror(err) +
         ". This kernel has no SocketCAN support (no can/can_raw modules). Run the SocketCAN path in the "
         "VM harness under vcan/ (see docs/vcan.md: a qemu guest with vcan0 and canplayer), or replay the "
         "log directly with --input log:FILE.";
}
}  // namespace

bool kernel_has_can() {
  int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

SocketCanInput::SocketCanInput(const std::string& iface, const std::vector<CanIdFilter>& ids)
    : iface_(iface), interface_drops_(iface) {
  const int probe = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (probe < 0) throw SocketCanError(no_can_message(errno));
  ::close(probe);
  if (ids.size() > CAN_RAW_FILTER_MAX)
    throw SocketCanError(iface + ": " + std::to_string(ids.size()) + " id filters, at most " +
                         std::to_string(CAN_RAW_FILTER_MAX) + " (one receive queue each)");
  const unsigned ifindex = if_nametoindex(iface.c_str());
  if (ifindex == 0)
    throw SocketCanError(iface + ": no such CAN interface (create it: ip link add dev " + iface +
                         " type vcan && ip link set up " + iface + "): " + std::strerror(ENODEV));
  try {
    epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
    if (epoll_ < 0) throw SocketCanError(iface + ": epoll_create1: " + std::strerror(errno));
    if (ids.empty()) {
      open_queue(ifindex, Takes::EveryFrame);
    } else {
      // Kernel-side filtering: the process never wakes up for frames the mapping does not use.
      // Remote frames pass too: they are counted (BusHealth), never decoded.
      for (const CanIdFilter& id : ids) open_queue(ifindex, Takes::OneId, &id);
      open_queue(ifindex, Takes::ErrorFrames);
    }
  } catch (...) {
    for (const ReceiveQueue& q : queues_) ::close(q.fd);
    if (epoll_ >= 0) ::close(epoll_);
    throw;
  }
  ready_.resize(queues_.size());
}

void SocketCanInput::open_queue(unsigned ifindex, Takes what, const CanIdFilter* id) {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) throw SocketCanError(iface_ + ": socket(PF_CAN): " + std::strerror(errno));
  auto fail = [&](const std::string& what) {
    const int e = errno;
    ::close(fd);
    throw SocketCanError(iface_ + ": " + what + ": " + std::strerror(e));
  };
  int on = 1;
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0) fail("enabling CAN FD frames");
  if (::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) != 0) fail("enabling kernel timestamps");
  // Without the drop counter a receive-queue overflow would lose frames silently: refuse.
  if (::setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) fail("enabling the drop counter (SO_RXQ_OVFL)");
  if (what != Takes::OneId) {
    const can_err_mask_t err_mask = CAN_ERR_MASK;
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0)
      fail("enabling error frames (CAN_RAW_ERR_FILTER)");
  }
  if (what == Takes::OneId) {
    can_filter cf{};
    cf.can_id = id->extended ? (id->id | CAN_EFF_FLAG) : id->id;
    cf.can_mask = CAN_EFF_FLAG | effective_mask(*id);
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, &cf, sizeof cf) != 0) fail("setting the id filter");
  } else if (what == Takes::ErrorFrames) {
    // An empty id filter list: no data frame at all, only what CAN_RAW_ERR_FILTER lets in.
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0) != 0) fail("clearing the id filters");
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(ifindex);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) fail("bind");
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u32 = static_cast<std::uint32_t>(queues_.size());
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &ev) != 0) fail("epoll_ctl");
  queues_.push_back({fd, 0});
}

SocketCanInput::~SocketCanInput() {
  for (const ReceiveQueue& q : queues_) ::close(q.fd);
  if (epoll_ >= 0) ::close(epoll_);
}

std::int64_t SocketCanInput::now_ns() const { return realtime_ns(); }  // kernel stamps' clock

std::string SocketCanInput::describe() const { return "SocketCAN " + iface_; }

bool SocketCanInput::drain(ReceiveQueue& queue) {
  // Bounded so the model still ticks and publishes under a flood: 256 frames is ~9 ms of a
  // full-rate cangen flood in the TCG guest (29 000 frames/s measured), under one 10 ms model
  // tick; 4096 was 140 ms. The cap loses nothing: what is left stays queued for the next poll;
  // only a full receive queue drops frames, and the kernel counts those (SO_RXQ_OVFL, stamped on
  // every frame queued after a drop).
  for (int i = 0; i < kMaxFramesPerPoll; ++i) {
    canfd_frame cf{};
    iovec iov{&cf, sizeof cf};
    alignas(cmsghdr) char ctrl[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = ctrl;
    msg.msg_controllen = sizeof ctrl;
    const ssize_t got = ::recvmsg(queue.fd, &msg, MSG_DONTWAIT);
    if (got < 0) return false;  // EAGAIN: drained
    CanFrame f;
    f.timestamp_ns = now_ns();
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
        timespec ts;
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        f.timestamp_ns = static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
      } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t d;
        std::memcpy(&d, CMSG_DATA(c), sizeof d);
        queue.drops = d;  // this socket's total since it was opened
      }
    }
    f.extended = (cf.can_id & CAN_EFF_FLAG) != 0;
    f.rtr = (cf.can_id & CAN_RTR_FLAG) != 0;
    f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
    f.id = cf.can_id & (f.error ? CAN_ERR_MASK : f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.fd = got == static_cast<ssize_t>(CANFD_MTU);
    if (f.fd) f.fd_flags = cf.flags & (CANFD_BRS | CANFD_ESI);
    f.len = std::min<std::uint8_t>(cf.len, f.fd ? 64 : 8);
    std::memcpy(f.data.data(), cf.data, f.len);
    batch_.push_back(f);
  }
  return true;
}

bool SocketCanInput::poll(InputSink& sink, std::chrono::milliseconds timeout) {
  const int n = ::epoll_wait(epoll_, ready_.data(), static_cast<int>(ready_.size()), static_cast<int>(timeout.count()));
  // A sysfs read is a system call and under a flood a poll comes every few hundred frames, so the
  // counter is read at most every kInterfaceDropsEvery: the count is at most that old (the run
  // loop polls at least every model tick, 10 ms, busy bus or quiet).
  const auto now = std::chrono::steady_clock::now();
  if (now >= interface_drops_due_) {
    health_.interface_drops = interface_drops_.read();
    interface_drops_due_ = now + kInterfaceDropsEvery;
  }
  if (n <= 0) return true;
  batch_.clear();
  bool capped = false;
  for (int k = 0; k < n; ++k) capped |= drain(queues_[ready_[static_cast<std::size_t>(k)].data.u32]);
  // Each queue is in order already; across queues the kernel's receive stamps give the bus order.
  std::stable_sort(batch_.begin(), batch_.end(),
                   [](const CanFrame& a, const CanFrame& b) { return a.timestamp_ns < b.timestamp_ns; });
  for (const CanFrame& f : batch_) {
    note_frame(health_, f);
    sink.on_frame(f);
  }
  std::uint64_t drops = 0;
  for (const ReceiveQueue& q : queues_) drops += q.drops;
  health_.kernel_drops = drops;
  if (capped) ++health_.deferred_polls;
  return true;
}

}  // namespace meter::controller
