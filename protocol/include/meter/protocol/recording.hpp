// The link recording: every message one end of the link received, one text line each, in the
// style of can-utils' candump -L. meter-linkdump prints and records it, meter-linkplay replays it.
// The text is the recording: it is lossless (integers exact, values in the shortest form that
// reads back to the same double, texts quoted with escapes), so a parsed line equals the frame
// that was formatted. Pure functions on plain data; docs/protocol.md ("Link recordings") has the
// grammar. One line:
//
//   (<received s.ns>) <KIND> seq=<u64> sent=<s.ns> <fields of the kind>
//   (12.000000042) DELTA seq=7 sent=11.999000000 Vehicle.Speed=103.25:valid Cluster.Text=0:valid:"P"
//
// Blank lines and lines starting with '#' are comments (meter-linkdump writes a '#' header).
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/wire.hpp"

namespace meter::protocol {

// One received message and when it arrived (CLOCK_MONOTONIC ns on the receiving machine; the
// sender's own stamp is frame.timestamp_ns).
struct RecordedFrame {
  std::int64_t received_ns = 0;
  Frame frame;
};

// What a bad line breaks, as "FILE:LINE: what was expected" (what() gives the whole text).
class RecordingError : public std::runtime_error {
 public:
  RecordingError(std::string file, std::size_t line, const std::string& message);
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }

 private:
  std::string file_;
  std::size_t line_;
};

// The first line meter-linkdump writes: names the format and the catalog it was recorded with.
inline constexpr std::string_view kRecordingFormat = "meter-link-recording/1";
std::string recording_header(std::uint64_t catalog_hash);

// One line, without the newline. Signal ids are written by catalog name; an id this build's
// catalog does not know (the decoder never lets one through) is written as #<id>.
std::string format_line(const RecordedFrame& recorded);
// The inverse of format_line. `file` and `line` only go into the RecordingError.
RecordedFrame parse_line(std::string_view text, std::string_view file, std::size_t line);
// Every message line of a recording, in order (comments skipped).
std::vector<RecordedFrame> parse_recording(std::istream& in, std::string_view file);

// Nanoseconds as "<s>.<9 digits>" (negative with a leading '-') and back; exact both ways.
std::string format_ns(std::int64_t ns);

}  // namespace meter::protocol
