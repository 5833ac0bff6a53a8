#include "transport/channel.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <variant>

#include "transport/log.hpp"

namespace meter::protocol::detail {

Channel::Channel(UniqueFd fd, bool stream, std::string label)
    : last_rx(Clock::now()), last_tx(Clock::now()), fd_(std::move(fd)), stream_(stream), label_(std::move(label)) {}

void Channel::send(const Message& message, LinkStats& stats) {
  Frame frame;
  frame.sequence = next_tx_seq_++;
  frame.timestamp_ns = monotonic_ns();
  frame.message = message;
  std::vector<std::uint8_t> bytes;
  encode(frame, bytes, guard_ ? guard_->tx_key(type_of(message)) : nullptr);
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
    case MessageType::Catalog: ++stats.catalog_pieces_sent; break;
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
    case DecodeError::BadMac: ++b.mac; key = "mac"; break;
    case DecodeError::MissingMac: ++b.no_mac; key = "no-mac"; break;
    case DecodeError::None: return;
  }
  log_limited(std::string("bad-frame-") + key,
              "dropped bad frame from " + label_ + ": " + std::string(to_string(r.error)) + ": " + r.detail);
}

bool Channel::accept_frame(DecodeResult& r, LinkStats& stats, const std::function<bool(Frame&&)>& on_frame,
                           ReadResult& fatal) {
  Frame& frame = r.frame;
  const std::uint64_t expected = last_rx_seq_ + 1;
  if (guard_) {
    bool close = false;
    r.error = guard_->check(r, r.detail, close);
    if (r.error != DecodeError::None) {
      count_bad(r, stats);
      if (close) fatal = {ReadOutcome::Fatal, CloseReason::Authentication, r.detail};
      return !close;  // a frame that fails its tag is dropped: it proves nothing, not even liveness
    }
    if (frame.sequence < expected) {
      ++stats.sequence_replays;
      log_limited("replay", "dropped " + std::string(to_string(type_of(frame.message))) + " from " + label_ +
                                ": sequence " + std::to_string(frame.sequence) + " was already used (replayed or reordered; expected " +
                                std::to_string(expected) + ")");
      return true;
    }
    if (frame.sequence > expected) {
      ++stats.sequence_gaps;
      stats.sequence_frames_missed += frame.sequence - expected;
      fatal = {ReadOutcome::Fatal, CloseReason::ProtocolError,
               std::to_string(frame.sequence - expected) + " frame(s) missing before sequence " +
                   std::to_string(frame.sequence) + " (dropped or held back on the way): resynchronising"};
      return false;
    }
  } else if (frame.sequence != expected) {
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
    case MessageType::Catalog: ++stats.catalog_pieces_received; break;
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
      ReadResult fatal;
      if (!accept_frame(r, stats, on_frame, fatal)) return fatal;
      continue;
    }
    stats.bytes_received += got;
    assembler_.append(std::span<const std::uint8_t>(rx_buffer_.data(), got));
    while (auto r = assembler_.next()) {
      if (r->error == DecodeError::None) {
        ReadResult fatal;
        if (!accept_frame(*r, stats, on_frame, fatal)) return fatal;
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

}  // namespace meter::protocol::detail
