// A whole candump -L log file: the frames it holds and the lines that break the grammar.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {

struct BadLine {
  std::size_t line;
  std::string why;
};

struct ParsedLog {
  std::vector<CanFrame> frames;
  std::vector<BadLine> bad_lines;  // skipped, with their line numbers
  std::size_t lines = 0;
};
ParsedLog parse_candump_log(std::string_view text);
ParsedLog load_candump_log(const std::string& path);  // throws std::runtime_error if unreadable

}  // namespace meter::controller
