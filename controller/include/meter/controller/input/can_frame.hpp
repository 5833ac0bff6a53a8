// One CAN / CAN FD frame as every input backend delivers it, plus the candump -L text form.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace meter::controller {

struct CanFrame {
  std::int64_t timestamp_ns = 0;  // log: the logged wall time; SocketCAN: kernel rx timestamp
  std::uint32_t id = 0;           // 11- or 29-bit identifier without flag bits (error frames: class bits)
  bool extended = false;          // 29-bit identifier
  bool rtr = false;               // remote request (no payload, len is the requested length)
  bool error = false;             // error frame (id holds the CAN_ERR_* class mask)
  bool fd = false;                // CAN FD frame
  std::uint8_t fd_flags = 0;      // CANFD_BRS = 1, CANFD_ESI = 2 (as candump writes them)
  std::uint8_t len = 0;           // payload bytes: 0..8 classic, 0..64 FD
  std::uint8_t len8_dlc = 0;      // classic frames with len 8: raw DLC 9..15 if the sender used one
  std::uint8_t input = 0;         // which of the controller's inputs (buses) delivered it, 0 = the first
  std::array<std::uint8_t, 64> data{};
};

inline constexpr std::uint8_t kCanFdBrs = 0x01;
inline constexpr std::uint8_t kCanFdEsi = 0x02;

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
bool is_valid_fd_len(std::size_t len);

// Now on CLOCK_REALTIME in ns: the clock of SocketCAN's kernel receive timestamps (SO_TIMESTAMPNS),
// so live frames, the model clock and the --trace rows compare directly.
std::int64_t realtime_ns();

}  // namespace meter::controller
