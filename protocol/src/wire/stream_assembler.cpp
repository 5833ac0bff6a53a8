// Reassembles frames from a byte stream (TCP) that arrives in arbitrary pieces.
#include "meter/protocol/wire.hpp"

namespace meter::protocol {

void StreamAssembler::append(std::span<const std::uint8_t> bytes) {
  if (broken_) return;
  if (start_ > 0 && start_ >= buffer_.size() / 2) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<DecodeResult> StreamAssembler::next() {
  if (broken_) return std::nullopt;
  // The frame returned last time stays readable (DecodeResult::bytes) until now.
  if (start_ > 0 && start_ == buffer_.size()) {
    buffer_.clear();
    start_ = 0;
  }
  const auto avail = std::span<const std::uint8_t>(buffer_).subspan(start_);
  DecodeResult res = peek_header(avail);
  if (res.error == DecodeError::Truncated) return std::nullopt;
  if (res.error == DecodeError::None) {
    if (avail.size() < res.frame_size) return std::nullopt;  // wait for the rest of the payload
    res = decode(avail.first(res.frame_size));
  }
  switch (res.error) {
    case DecodeError::None:
    case DecodeError::UnknownType:
    case DecodeError::Malformed:
      start_ += res.frame_size;  // CRC was good, so the length is trustworthy: skip exactly this frame
      return res;
    default:
      broken_ = true;
      buffer_.clear();
      buffer_.shrink_to_fit();
      start_ = 0;
      return res;
  }
}

}  // namespace meter::protocol
