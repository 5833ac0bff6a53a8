// One connected socket of the link: framing (one datagram per frame on SOCK_SEQPACKET, a
// StreamAssembler on TCP), the output queue, sequence numbers, and bad-input handling (count,
// log, drop, or close when the framing is lost).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "transport/clock.hpp"
#include "transport/frame_guard.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"
#include "transport/unique_fd.hpp"

namespace meter::protocol::detail {

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
  // An authenticated connection: frames are tagged as the guard says and received ones checked
  // by it; sequence numbers are then strict (an old one is dropped as a replay, a skipped one
  // closes the connection so the peer resynchronises with a fresh SNAPSHOT).
  void guard(std::unique_ptr<FrameGuard> guard) { guard_ = std::move(guard); }
  FrameGuard* guard() const { return guard_.get(); }

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
  // Tag and sequence checks, then on_frame. False: stop reading (on_frame said so, or `fatal` set).
  bool accept_frame(DecodeResult& r, LinkStats& stats, const std::function<bool(Frame&&)>& on_frame,
                    ReadResult& fatal);

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
  std::unique_ptr<FrameGuard> guard_;
};

}  // namespace meter::protocol::detail
