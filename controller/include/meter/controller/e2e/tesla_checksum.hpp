// Tesla (Model S/X chassis and party buses): the checksum byte is the low byte of the sum of the
// id's two bytes and every other payload byte (opendbc's documented Tesla checksum; its place is
// the DBC's checksum signal).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t tesla_checksum(std::uint32_t id, std::span<const std::uint8_t> payload, std::size_t checksum_byte);

}  // namespace meter::controller
