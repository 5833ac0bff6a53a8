// The lines of a text log, read from a stream a block at a time (a long log is never held whole
// in memory), each handed over without its line end.
#pragma once

#include <functional>
#include <istream>
#include <string_view>
#include <vector>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {

// Calls each_line(line) for every line of `in` in order, the line without '\n' and without the
// spaces, tabs and carriage return at its end (trim_line_end); blank lines are handed over too.
void for_each_log_line(std::istream& in, const std::function<void(std::string_view)>& each_line);
// Room in `frames` for the frames a stream of that many bytes per frame holds (its size told by
// seeking to its end and back): the frames are not moved as they grow.
void reserve_log_frames(std::istream& in, std::size_t bytes_per_frame, std::vector<CanFrame>& frames);

// The same over text already in memory.
void for_each_log_line(std::string_view text, const std::function<void(std::string_view)>& each_line);

}  // namespace meter::controller
