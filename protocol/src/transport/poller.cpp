#include "transport/poller.hpp"

#include <sys/epoll.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace meter::protocol::detail {

Poller::Poller(std::chrono::milliseconds tick) {
  epoll_.reset(::epoll_create1(EPOLL_CLOEXEC));
  if (!epoll_) throw std::runtime_error("epoll_create1 failed: " + errno_text(errno));
  timer_.reset(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC));
  if (!timer_) throw std::runtime_error("timerfd_create failed: " + errno_text(errno));
  const auto ns = std::max<std::int64_t>(std::chrono::nanoseconds(tick).count(), 1'000'000);
  itimerspec spec{};
  spec.it_interval.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  spec.it_interval.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  spec.it_value = spec.it_interval;
  if (::timerfd_settime(timer_.get(), 0, &spec, nullptr) != 0) {
    throw std::runtime_error("timerfd_settime failed: " + errno_text(errno));
  }
  add(timer_.get(), false);
}

void Poller::add(int fd, bool want_write) {
  epoll_event ev{};
  ev.events = EPOLLIN | (want_write ? EPOLLOUT : 0U);
  ev.data.fd = fd;
  if (::epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, fd, &ev) != 0) {
    throw std::runtime_error("epoll_ctl(ADD) failed: " + errno_text(errno));
  }
}

void Poller::modify(int fd, bool want_write) {
  epoll_event ev{};
  ev.events = EPOLLIN | (want_write ? EPOLLOUT : 0U);
  ev.data.fd = fd;
  ::epoll_ctl(epoll_.get(), EPOLL_CTL_MOD, fd, &ev);
}

void Poller::remove(int fd) { ::epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, fd, nullptr); }

std::vector<int> Poller::wait(int timeout_ms) {
  epoll_event events[64];
  std::vector<int> ready;
  int n = ::epoll_wait(epoll_.get(), events, 64, timeout_ms);
  if (n < 0) return ready;  // EINTR: the caller's loop just goes round again
  for (int i = 0; i < n; ++i) {
    if (events[i].data.fd == timer_.get()) {
      std::uint64_t ticks = 0;
      [[maybe_unused]] auto r = ::read(timer_.get(), &ticks, sizeof ticks);
      continue;
    }
    ready.push_back(events[i].data.fd);
  }
  return ready;
}

}  // namespace meter::protocol::detail
