// The wait set of one Publisher or Subscriber: an epoll set plus a periodic timerfd, so wait_fd()
// wakes the caller for heartbeats and timeouts too.
#pragma once

#include <chrono>
#include <vector>

#include "transport/unique_fd.hpp"

namespace meter::protocol::detail {

class Poller {
 public:
  explicit Poller(std::chrono::milliseconds tick);
  int fd() const { return epoll_.get(); }
  void add(int fd, bool want_write);
  void modify(int fd, bool want_write);
  void remove(int fd);
  // Waits up to timeout_ms (0 = don't block) and returns the ready fds (timer ticks are drained
  // and not returned).
  std::vector<int> wait(int timeout_ms);

 private:
  UniqueFd epoll_;
  UniqueFd timer_;
};

}  // namespace meter::protocol::detail
