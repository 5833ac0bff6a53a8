// Shared internals of Publisher and Subscriber: clock, fd ownership, rate-limited logging, and the
// Channel (one connected socket: framing, output queue, sequence numbers, bad-input handling).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux: the sender timestamp base
std::int64_t monotonic_ns();

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd() { reset(); }
  UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) reset(o.release());
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  int release() {
    int f = fd_;
    fd_ = -1;
    return f;
  }
  void reset(int fd = -1);

 private:
  int fd_ = -1;
};

std::string errno_text(int err);
void set_nonblocking(int fd);

// Token bucket per event key: a burst of 5 lines, then one per second; suppressed lines are
// counted and reported with the next line that gets through.
void log_limited(std::string_view key, const std::string& line);

// Epoll set plus a periodic timerfd, so wait_fd() wakes the caller for heartbeats/timeouts too.
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

enum class ReadOutcome { Ok, PeerClosed, Fatal };

struct ReadResult {
  ReadOutcome outcome = ReadOutcome::Ok;
  CloseReason reason = CloseReason::ProtocolError;  // for Fatal
  std::string detail;
};

class Channel {
 public:
  Channel(UniqueFd fd, bool stream, std::string label);
  int fd() const { return fd_.get(); }
  bool stream() const { return stream_; }
  const std::string& label() const { return label_; }
  void set_label(std::string label) { label_ = std::move(label); }

  // Encodes with the next sequence number and the current time, and queues the frame.
  void send(const Message& message, LinkStats& stats);
  std::size_t pending_bytes() const { return out_bytes_; }
  bool has_pending() const { return out_bytes_ > 0; }
  // Writes as much of the queue as the socket takes. False (with `error`) if the peer is gone.
  bool flush(LinkStats& stats, std::string& error);
  // Reads what is available (bounded per call), delivers good frames to `on_frame`, counts, logs and
  // drops bad ones; Fatal when the connection must close (framing lost, wrong version).
  // `on_frame` returns false to stop reading (the session is ending); receive() then returns Ok
  // at once and the caller may destroy the channel.
  ReadResult receive(LinkStats& stats, const std::function<bool(Frame&&)>& on_frame);

  Clock::time_point last_rx;
  Clock::time_point last_tx;

 private:
  void count_bad(const DecodeResult& r, LinkStats& stats);
  bool accept_frame(Frame&& frame, LinkStats& stats, const std::function<bool(Frame&&)>& on_frame);

  UniqueFd fd_;
  bool stream_;
  std::string label_;
  StreamAssembler assembler_;
  std::deque<std::vector<std::uint8_t>> out_;
  std::size_t out_offset_ = 0;  // bytes of out_.front() already written (stream only)
  std::size_t out_bytes_ = 0;
  std::uint64_t next_tx_seq_ = 1;
  std::uint64_t last_rx_seq_ = 0;
  std::vector<std::uint8_t> rx_buffer_;
};

std::string hex64(std::uint64_t v);

// Checks a received HELLO against this build; "" if acceptable, else the refusal text.
std::string check_hello(const Hello& hello, Role expected_role, std::uint64_t our_hash, CloseReason& reason);

}  // namespace meter::protocol::detail
