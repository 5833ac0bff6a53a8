// Subaru pre-global platform (and the Toyota 86 / Subaru BRZ built on it): the checksum byte is
// the low byte of the sum of every other payload byte, the id left out (openpilot's documented
// pre-global checksum; its place is the DBC's Checksum signal, e.g. byte 4 of Steering 0x002).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t subaru_preglobal_checksum(std::span<const std::uint8_t> payload, std::size_t checksum_byte);

}  // namespace meter::controller
