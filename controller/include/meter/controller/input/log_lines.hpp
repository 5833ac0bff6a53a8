// The lines of a text log, read from a stream a block at a time (a long log is never held whole
// in memory), each handed over without its line end.
#pragma once

#include <functional>
#include <istream>
#include <string_view>
#include <vector>

#include "meter/controller/input/can_frame.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// Calls each_line(line) for every line of `in` in order, the line without '\n' and without the
// spaces, tabs and carriage return at its end (trim_line_end); blank lines are handed over too.
void for_each_log_line(std::istream& in, const std::function<void(std::string_view)>& each_line);
// Room in `frames` for the frames a stream of that many bytes per frame holds (its size told by
// seeking to its end and back): the frames are not moved as they grow.
void reserve_log_frames(std::istream& in, std::size_t bytes_per_frame, std::vector<CanFrame>& frames);

// The same over text already in memory.
void for_each_log_line(std::string_view text, const std::function<void(std::string_view)>& each_line);

// A whole text log through a line reader (a class with `void line(std::string_view)` and a
// `ParsedLog log`): from a stream, room reserved for a frame every `bytes_per_frame` bytes.
template <class LineReader>
ParsedLog read_log_lines(std::istream& in, std::size_t bytes_per_frame) {
  LineReader reader;
  reserve_log_frames(in, bytes_per_frame, reader.log.frames);
  for_each_log_line(in, [&](std::string_view line) { reader.line(line); });
  return std::move(reader.log);
}
template <class LineReader>
ParsedLog read_log_lines(std::string_view text) {
  LineReader reader;
  for_each_log_line(text, [&](std::string_view line) { reader.line(line); });
  return std::move(reader.log);
}

}  // namespace meter::controller
