// Fuzzes the decoder three ways on every input: as one datagram, as a TCP stream cut at an
// input-derived point, and (for inputs that decode) through a re-encode round trip, which must
// reproduce the same message. A tagged frame (an authenticated link's) is re-encoded tagged: its
// bytes up to the tag must come back, the tag is the MAC's business (frame_tag.hpp), not the
// decoder's. Any crash, sanitizer report or broken invariant is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/wire.hpp"

using namespace meter::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);

  const DecodeResult r = decode(bytes);
  if (r.error == DecodeError::None) {
    if (r.frame_size > size || r.frame_size < kHeaderSize) std::abort();
    // Everything the decoder accepts, the encoder must be able to write back identically.
    const FrameKey any_key{};
    const bool tagged = r.header.tagged();
    const auto again = encode(r.frame, tagged ? &any_key : nullptr);
    if (again.size() != r.frame_size) std::abort();
    const DecodeResult r2 = decode(again);
    if (r2.error != DecodeError::None || !(r2.frame.message == r.frame.message) ||
        r2.frame.sequence != r.frame.sequence || r2.frame.timestamp_ns != r.frame.timestamp_ns) {
      std::abort();
    }
    if (r.bytes.size() != r.frame_size || r.bytes.data() != data) std::abort();
    if (tagged != frame_tag_matches(again, any_key)) std::abort();
    for (std::size_t i = 0; i < r.frame_size - (tagged ? kTagSize : 0); ++i) {
      if (again[i] != data[i]) std::abort();  // the format has exactly one encoding per message
    }
  }

  // Stream path: the same bytes in two pieces, split where the first byte says.
  StreamAssembler stream;
  const std::size_t cut = size == 0 ? 0 : data[0] % (size + 1);
  stream.append(bytes.first(cut));
  std::size_t frames = 0;
  while (auto f = stream.next()) ++frames;
  stream.append(bytes.subspan(cut));
  while (auto f = stream.next()) {
    if (f->error == DecodeError::None && f->frame_size < kHeaderSize) std::abort();
    ++frames;
  }
  if (stream.buffered() > size) std::abort();
  (void)frames;
  return 0;
}
