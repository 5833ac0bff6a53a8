#include <fcntl.h>
#include <netinet/in.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "internal.hpp"

namespace meter::protocol {

// ---- Endpoint -------------------------------------------------------------------------------

Endpoint Endpoint::parse(std::string_view text) {
  const std::string quoted = "endpoint '" + std::string(text) + "': ";
  Endpoint e;
  if (text.starts_with("unix:")) {
    e.kind = Kind::Unix;
    e.path = std::string(text.substr(5));
    if (e.path.empty()) throw std::invalid_argument(quoted + "the unix socket path is empty");
    if (e.path.find('\0') != std::string::npos) throw std::invalid_argument(quoted + "path contains a NUL byte");
    constexpr std::size_t limit = sizeof(sockaddr_un::sun_path) - 1;
    if (e.path.size() > limit) {
      throw std::invalid_argument(quoted + "the unix socket path is " + std::to_string(e.path.size()) +
                                  " bytes; the kernel limit is " + std::to_string(limit));
    }
    return e;
  }
  if (text.starts_with("tcp:")) {
    e.kind = Kind::Tcp;
    std::string_view rest = text.substr(4);
    std::string_view port_text;
    if (rest.starts_with("[")) {
      const auto close = rest.find(']');
      if (close == std::string_view::npos) throw std::invalid_argument(quoted + "'[' of an IPv6 host is not closed");
      e.host = std::string(rest.substr(1, close - 1));
      rest = rest.substr(close + 1);
      if (!rest.starts_with(":")) throw std::invalid_argument(quoted + "expected ':PORT' after ']'");
      port_text = rest.substr(1);
    } else {
      const auto colon = rest.rfind(':');
      if (colon == std::string_view::npos) throw std::invalid_argument(quoted + "expected tcp:HOST:PORT");
      e.host = std::string(rest.substr(0, colon));
      if (e.host.find(':') != std::string::npos) {
        throw std::invalid_argument(quoted + "an IPv6 host must be written in brackets: tcp:[::1]:PORT");
      }
      port_text = rest.substr(colon + 1);
    }
    if (e.host.empty()) throw std::invalid_argument(quoted + "the host is empty");
    unsigned port = 0;
    const auto* end = port_text.data() + port_text.size();
    auto [ptr, ec] = std::from_chars(port_text.data(), end, port);
    if (port_text.empty() || ec != std::errc() || ptr != end || port > 65535) {
      throw std::invalid_argument(quoted + "port '" + std::string(port_text) + "' is not a number 0..65535");
    }
    e.port = static_cast<std::uint16_t>(port);
    return e;
  }
  throw std::invalid_argument(quoted + "expected unix:/path/to.sock or tcp:HOST:PORT");
}

std::string Endpoint::to_string() const {
  if (kind == Kind::Unix) return "unix:" + path;
  const bool v6 = host.find(':') != std::string::npos;
  return "tcp:" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

Endpoint default_endpoint() {
  Endpoint e;
  e.kind = Endpoint::Kind::Unix;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime != nullptr && runtime[0] == '/') {
    e.path = std::string(runtime) + "/meter.sock";
  } else {
    e.path = "/tmp/meter-" + std::to_string(::getuid()) + "/meter.sock";
  }
  return e;
}

// ---- logging --------------------------------------------------------------------------------

namespace {
std::mutex g_log_mutex;
LogSink g_sink;

struct Bucket {
  double tokens = 5.0;
  detail::Clock::time_point last{};
  std::uint64_t suppressed = 0;
};
std::map<std::string, Bucket, std::less<>> g_buckets;
}  // namespace

void set_log_sink(LogSink sink) {
  std::lock_guard lock(g_log_mutex);
  g_sink = std::move(sink);
  g_buckets.clear();  // a new sink starts with full budgets: it sees the first lines of each kind
}

namespace detail {

void log_limited(std::string_view key, const std::string& line) {
  std::lock_guard lock(g_log_mutex);
  const auto now = Clock::now();
  auto it = g_buckets.find(key);
  if (it == g_buckets.end()) it = g_buckets.emplace(std::string(key), Bucket{5.0, now, 0}).first;
  Bucket& b = it->second;
  b.tokens = std::min(5.0, b.tokens + std::chrono::duration<double>(now - b.last).count());
  b.last = now;
  if (b.tokens < 1.0) {
    ++b.suppressed;
    return;
  }
  b.tokens -= 1.0;
  std::string text = "meter-protocol: " + line;
  if (b.suppressed > 0) {
    text += " (" + std::to_string(b.suppressed) + " similar message(s) suppressed)";
    b.suppressed = 0;
  }
  if (g_sink) {
    g_sink(text);
  } else {
    std::fprintf(stderr, "%s\n", text.c_str());
  }
}

std::int64_t monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void UniqueFd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

std::string errno_text(int err) { return std::strerror(err); }

void set_nonblocking(int fd) {
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
    throw std::runtime_error("fcntl(O_NONBLOCK) failed: " + errno_text(errno));
  }
}

std::string hex64(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// ---- Poller ---------------------------------------------------------------------------------

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

// ---- Channel --------------------------------------------------------------------------------

Channel::Channel(UniqueFd fd, bool stream, std::string label)
    : last_rx(Clock::now()), last_tx(Clock::now()), fd_(std::move(fd)), stream_(stream), label_(std::move(label)) {}

void Channel::send(const Message& message, LinkStats& stats) {
  Frame frame;
  frame.sequence = next_tx_seq_++;
  frame.timestamp_ns = monotonic_ns();
  frame.message = message;
  std::vector<std::uint8_t> bytes;
  encode(frame, bytes);
  out_bytes_ += bytes.size();
  out_.push_back(std::move(bytes));
  stats.max_pending_bytes = std::max<std::uint64_t>(stats.max_pending_bytes, out_bytes_);
  ++stats.messages_sent;
  switch (type_of(message)) {
    case MessageType::Hello: ++stats.hellos_sent; break;
    case MessageType::Snapshot:
      ++stats.snapshots_sent;
      stats.signal_updates_sent += std::get<Snapshot>(message).signals.size();
      break;
    case MessageType::Delta:
      ++stats.deltas_sent;
      stats.signal_updates_sent += std::get<Delta>(message).signals.size();
      break;
    case MessageType::Heartbeat: ++stats.heartbeats_sent; break;
    case MessageType::Status: ++stats.status_sent; break;
    case MessageType::Close: break;
  }
  last_tx = Clock::now();
}

bool Channel::flush(LinkStats& stats, std::string& error) {
  while (!out_.empty()) {
    const auto& front = out_.front();
    const ssize_t n = ::send(fd_.get(), front.data() + out_offset_, front.size() - out_offset_,
                             MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        ++stats.write_stalls;
        return true;
      }
      error = "send failed: " + errno_text(errno);
      return false;
    }
    stats.bytes_sent += static_cast<std::uint64_t>(n);
    out_offset_ += static_cast<std::size_t>(n);  // SEQPACKET sends all or nothing; TCP may be partial
    out_bytes_ -= static_cast<std::size_t>(n);
    if (out_offset_ == front.size()) {
      out_.pop_front();
      out_offset_ = 0;
    }
  }
  return true;
}

void Channel::count_bad(const DecodeResult& r, LinkStats& stats) {
  auto& b = stats.bad_frames;
  const char* key = "bad";
  switch (r.error) {
    case DecodeError::Truncated: ++b.truncated; key = "truncated"; break;
    case DecodeError::BadMagic: ++b.bad_magic; key = "magic"; break;
    case DecodeError::BadVersion: ++b.version; key = "version"; break;
    case DecodeError::Oversized: ++b.oversized; key = "oversized"; break;
    case DecodeError::BadCrc: ++b.crc; key = "crc"; break;
    case DecodeError::UnknownType: ++b.unknown_type; key = "type"; break;
    case DecodeError::Malformed: ++b.malformed; key = "malformed"; break;
    case DecodeError::None: return;
  }
  log_limited(std::string("bad-frame-") + key,
              "dropped bad frame from " + label_ + ": " + std::string(to_string(r.error)) + ": " + r.detail);
}

bool Channel::accept_frame(Frame&& frame, LinkStats& stats, const std::function<bool(Frame&&)>& on_frame) {
  const std::uint64_t expected = last_rx_seq_ + 1;
  if (frame.sequence != expected) {
    ++stats.sequence_gaps;
    if (frame.sequence > expected) stats.sequence_frames_missed += frame.sequence - expected;
    log_limited("sequence-gap", "sequence gap from " + label_ + ": expected " + std::to_string(expected) +
                                    ", got " + std::to_string(frame.sequence));
  }
  last_rx_seq_ = frame.sequence;
  last_rx = Clock::now();
  ++stats.messages_received;
  switch (type_of(frame.message)) {
    case MessageType::Hello: ++stats.hellos_received; break;
    case MessageType::Snapshot: ++stats.snapshots_received; break;
    case MessageType::Delta: ++stats.deltas_received; break;
    case MessageType::Heartbeat: ++stats.heartbeats_received; break;
    case MessageType::Status: ++stats.status_received; break;
    case MessageType::Close: break;
  }
  return on_frame(std::move(frame));
}

ReadResult Channel::receive(LinkStats& stats, const std::function<bool(Frame&&)>& on_frame) {
  // Bounded work per call so one chatty peer cannot starve the others or the caller's loop.
  constexpr int kMaxReads = 64;
  if (rx_buffer_.empty()) rx_buffer_.resize(kMaxFrameSize + 1);
  for (int i = 0; i < kMaxReads; ++i) {
    const ssize_t n = ::recv(fd_.get(), rx_buffer_.data(), rx_buffer_.size(),
                             MSG_DONTWAIT | (stream_ ? 0 : MSG_TRUNC));
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) return {};
      return {ReadOutcome::PeerClosed, CloseReason::Normal, "receive failed: " + errno_text(errno)};
    }
    if (n == 0) return {ReadOutcome::PeerClosed, CloseReason::Normal, "peer closed the connection"};
    const auto got = static_cast<std::size_t>(n);
    if (!stream_) {
      stats.bytes_received += got;
      // One datagram = one frame. MSG_TRUNC reports the real length even if it did not fit.
      if (got > rx_buffer_.size()) {
        DecodeResult r;
        r.error = DecodeError::Oversized;
        r.detail = "datagram of " + std::to_string(got) + " bytes exceeds the frame limit of " +
                   std::to_string(kMaxFrameSize);
        count_bad(r, stats);
        continue;
      }
      DecodeResult r = decode(std::span<const std::uint8_t>(rx_buffer_.data(), got));
      if (r.error == DecodeError::None && r.frame_size != got) {
        r.error = DecodeError::Malformed;
        r.detail = "datagram has " + std::to_string(got - r.frame_size) + " byte(s) after the frame";
      }
      if (r.error == DecodeError::BadVersion) {
        count_bad(r, stats);
        return {ReadOutcome::Fatal, CloseReason::VersionMismatch, r.detail};
      }
      if (r.error != DecodeError::None) {
        count_bad(r, stats);
        continue;  // datagram boundaries survive a bad frame: drop it and carry on
      }
      if (!accept_frame(std::move(r.frame), stats, on_frame)) return {};
      continue;
    }
    stats.bytes_received += got;
    assembler_.append(std::span<const std::uint8_t>(rx_buffer_.data(), got));
    while (auto r = assembler_.next()) {
      if (r->error == DecodeError::None) {
        if (!accept_frame(std::move(r->frame), stats, on_frame)) return {};
        continue;
      }
      count_bad(*r, stats);
      if (assembler_.broken()) {
        return {ReadOutcome::Fatal,
                r->error == DecodeError::BadVersion ? CloseReason::VersionMismatch : CloseReason::ProtocolError,
                "stream framing lost: " + std::string(to_string(r->error)) + ": " + r->detail};
      }
    }
  }
  return {};
}

std::string check_hello(const Hello& hello, Role expected_role, std::uint64_t our_hash, CloseReason& reason) {
  if (hello.protocol_version != kProtocolVersion) {
    reason = CloseReason::VersionMismatch;
    return "peer speaks protocol version " + std::to_string(hello.protocol_version) + ", this build speaks " +
           std::to_string(kProtocolVersion);
  }
  if (hello.role != expected_role) {
    reason = CloseReason::RoleMismatch;
    return "peer says it is a " + std::string(to_string(hello.role)) + ", expected a " +
           std::string(to_string(expected_role));
  }
  if (hello.catalog_hash != our_hash) {
    reason = CloseReason::CatalogMismatch;
    return "signal catalog mismatch: peer catalog hash " + hex64(hello.catalog_hash) + " (" +
           std::to_string(hello.signal_count) + " signals), ours " + hex64(our_hash) + " (" +
           std::to_string(catalog().size()) + " signals); rebuild controller and view from the same protocol/ catalog";
  }
  return {};
}

}  // namespace detail
}  // namespace meter::protocol
