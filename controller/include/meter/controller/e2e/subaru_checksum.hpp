// Subaru global platform: byte 0 is the low byte of the sum of the id's bytes and payload bytes
// 1..n-1 (opendbc's documented Subaru checksum, subaru_global_*.dbc).
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t subaru_checksum(std::uint32_t id, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
