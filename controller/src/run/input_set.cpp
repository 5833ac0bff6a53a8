// Several inputs polled as one on one clock.
#include <sys/epoll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "meter/controller/run/input_set.hpp"

namespace meter::controller {

namespace {

// Tags one member's frames with its input index and moves its timestamps onto the time base.
class OntoTimeBase : public InputSink {
 public:
  OntoTimeBase(InputSink& sink, int tag, std::int64_t offset_ns) : sink_(sink), tag_(tag), offset_(offset_ns) {}
  void on_frame(const CanFrame& f) override {
    CanFrame g = f;
    if (tag_ >= 0) g.input = static_cast<std::uint8_t>(tag_);
    g.timestamp_ns += offset_;
    sink_.on_frame(g);
  }
  void on_value(std::string_view key, double v, bool valid, std::int64_t t) override { sink_.on_value(key, v, valid, t + offset_); }

 private:
  InputSink& sink_;
  int tag_;
  std::int64_t offset_;
};

}  // namespace

InputSet::InputSet(std::vector<Member> members) : members_(std::move(members)), ended_(members_.size(), false) {
  if (members_.empty()) throw std::invalid_argument("InputSet: no inputs");
  for (const Member& m : members_) {
    const std::optional<int> fd = m.input->wait_fd();
    if (!fd) continue;
    if (epoll_ < 0 && (epoll_ = ::epoll_create1(EPOLL_CLOEXEC)) < 0)
      throw std::runtime_error(std::string("epoll_create1: ") + std::strerror(errno));
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.fd = *fd;
    if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, *fd, &ev) != 0) {
      const int e = errno;
      ::close(epoll_);
      throw std::runtime_error(m.input->describe() + ": epoll_ctl: " + std::strerror(e));
    }
  }
}

InputSet::~InputSet() {
  if (epoll_ >= 0) ::close(epoll_);
}

bool InputSet::poll(InputSink& sink, std::chrono::milliseconds timeout) {
  // Sleep until a bus has frames or the caller's deadline (the next model tick).
  if (epoll_ >= 0) {
    epoll_event ev[8];
    ::epoll_wait(epoll_, ev, 8, static_cast<int>(timeout.count()));
  } else if (timeout.count() > 0) {
    std::this_thread::sleep_for(timeout);
  }
  for (std::size_t i = 0; i < members_.size(); ++i) {
    if (ended_[i]) continue;
    Input& in = *members_[i].input;
    const std::int64_t offset = i == 0 ? 0 : now_ns() - in.now_ns();
    OntoTimeBase onto(sink, members_[i].tag, offset);
    ended_[i] = !in.poll(onto, std::chrono::milliseconds(0));
  }
  return !ended_.front();
}

BusHealth InputSet::health() const {
  BusHealth total;
  for (const Member& m : members_) add_health(total, m.input->health());
  return total;
}

std::string InputSet::describe() const {
  std::string d;
  for (const Member& m : members_)
    d += (d.empty() ? "" : " + ") + (m.name.empty() ? "" : m.name + ": ") + m.input->describe();
  return d;
}

}  // namespace meter::controller
