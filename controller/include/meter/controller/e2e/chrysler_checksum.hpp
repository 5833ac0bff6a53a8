// Chrysler / FCA (CUSW, Pacifica, RAM): the last byte is CRC-8 SAE J1850 (0x1D, initial and final
// XOR 0xFF) over every byte before it. opendbc documents it as a bitwise loop taken from Miller and
// Valasek's "Remote Exploitation of an Unaltered Passenger Vehicle"; it is the J1850 CRC.
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t chrysler_checksum(std::span<const std::uint8_t> payload);

}  // namespace meter::controller
