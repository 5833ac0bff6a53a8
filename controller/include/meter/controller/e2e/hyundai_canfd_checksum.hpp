// Hyundai / Kia / Genesis on CAN FD (hyundai_canfd.dbc): a 16-bit CRC in bytes 0-1, the CRC-16
// 0x1021 register from 0 over payload bytes 2..n-1, then the id's low and high byte, XORed with a
// constant per frame length (8, 16, 24, 32 bytes) (opendbc's documented HKG CAN FD checksum).
#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace meter::controller {

// nullopt for a frame length the rule does not define.
std::optional<std::uint16_t> hyundai_canfd_checksum(std::uint32_t id, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
