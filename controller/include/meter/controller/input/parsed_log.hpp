// A recorded CAN log once parsed, whatever its format: the frames it holds, in file order, and the
// records (lines) that broke the format's grammar.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {

struct BadLine {
  std::size_t line;  // 1-based line of a text format (a binary format: its record number, 0 its file header)
  std::string why;   // what was expected there
};

struct ParsedLog {
  std::string_view format = "candump";  // the name of its LogFormat (several merged: the first's)
  std::vector<CanFrame> frames;
  std::vector<BadLine> bad_lines;  // skipped, with their line numbers
  std::size_t lines = 0;           // text: lines read; binary: objects read
  std::size_t skipped = 0;         // records of kinds that hold no CAN frame (ASC statistics, BLF objects of
                                   // other buses, TRC status lines): passed over by design and counted
};

}  // namespace meter::controller
