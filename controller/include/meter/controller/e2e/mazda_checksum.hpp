// Mazda (CX-5, Mazda 3 gen 1: CAM_LKAS and the messages laid out like it): the last byte is
// 249 minus both nibbles of byte 0 minus every byte between, modulo 256 (openpilot's mazdacan.py,
// its worked example "b8 00 00 20 02 00 00 c4").
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t mazda_checksum(std::span<const std::uint8_t> payload);

}  // namespace meter::controller
