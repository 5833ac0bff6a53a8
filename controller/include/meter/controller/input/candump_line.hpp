// The candump -L text form of a CAN frame, one line each way (can-utils' grammar), and the CAN FD
// length rules it checks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {

// The result of parsing one candump -L line.
struct CandumpLine {
  CanFrame frame;
  std::string interface;
};

// Parses "(1631416514.717133) can0 0D2#0000FFFF10000000" in the full can-utils grammar:
// 3-digit (standard) and 8-digit (extended) ids, error frames (8 digits with CAN_ERR_FLAG),
// "#R" / "#R<len>" remote frames, raw DLC suffix "_9".."_F", CAN FD "##<flags><data>", optional '.'
// separators between data bytes and an optional trailing direction token (R/T).
// Returns nullopt and fills *why with what was expected where the line breaks the grammar.
std::optional<CandumpLine> parse_candump_line(std::string_view line, std::string* why);

// Parses just the frame part ("123#DEADBEEF", "123##1AABB"), timestamp left 0.
std::optional<CanFrame> parse_frame_text(std::string_view text, std::string* why);

// Writes a frame in candump -L form (the same bytes can-utils' candump -L writes).
std::string format_candump_line(const CanFrame& frame, std::string_view interface);

// FD length <-> DLC mapping (ISO 11898-1).
std::uint8_t can_fd_dlc_to_len(std::uint8_t dlc);
std::uint8_t can_fd_len_to_dlc(std::size_t len);  // the smallest DLC that holds len bytes (len <= 64)
bool is_valid_fd_len(std::size_t len);

}  // namespace meter::controller
