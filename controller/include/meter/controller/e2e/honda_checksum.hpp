// Honda / Acura: a 4-bit checksum in the low nibble of the last byte: 8 minus the sum of every
// nibble of the id and of the payload (the checksum nibble left out), plus 3 for an extended id,
// modulo 16 (opendbc's documented Honda checksum).
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t honda_checksum(std::uint32_t id, bool extended, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
