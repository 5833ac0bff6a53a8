// Toyota / Lexus: the last byte is the low byte of the sum of the frame length, the id's bytes
// and every payload byte before it (opendbc's documented Toyota checksum, its CHECKSUM signals).
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t toyota_checksum(std::uint32_t id, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
