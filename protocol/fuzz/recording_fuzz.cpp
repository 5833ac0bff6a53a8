// Fuzzes the link-recording reader (what meter-linkplay replays) as linkplay uses it: parse the
// whole text, then every parsed frame must encode for the wire (the parser promises only frames
// the encoder accepts), decode back to the same message, and format to a line that parses back to
// the same frame (the format is lossless). A crash, a sanitizer report, an exception other than
// RecordingError, or a broken invariant is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "meter/protocol/recording.hpp"
#include "meter/protocol/wire.hpp"

using namespace meter::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<RecordedFrame> frames;
  try {
    frames = parse_recording(in, "fuzz.rec");
  } catch (const RecordingError&) {
    return 0;
  }
  for (const RecordedFrame& f : frames) {
    const auto bytes = encode(f.frame);
    const DecodeResult d = decode(bytes);
    if (d.error != DecodeError::None || !(d.frame.message == f.frame.message)) std::abort();
    const RecordedFrame back = parse_line(format_line(f), "again.rec", 1);
    if (back.received_ns != f.received_ns || back.frame.sequence != f.frame.sequence ||
        back.frame.timestamp_ns != f.frame.timestamp_ns || !(back.frame.message == f.frame.message)) {
      std::abort();
    }
  }
  return 0;
}
