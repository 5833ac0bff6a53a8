// One CAN / CAN FD frame as every input backend delivers it.
#pragma once

#include <array>
#include <cstdint>

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
  std::uint8_t channel = 0;       // a recorded log's channel as the file numbers it (ASC, BLF, TRC bus: 1..;
                                  // candump: its interfaces in order of first appearance, 1..); 0 = none
  std::array<std::uint8_t, 64> data{};
};

inline constexpr std::uint8_t kCanFdBrs = 0x01;
inline constexpr std::uint8_t kCanFdEsi = 0x02;

}  // namespace meter::controller
