// Nissan (X-Trail, Leaf, Rogue: the LKAS message's CHECKSUM): the last byte is CRC-8 with
// polynomial 0x1D over the bytes before it, which openpilot's nissancan.py states as crcmod's
// mkCrcFun(0x11D, initCrc=0x00, xorOut=0xFF); crcmod's initCrc is the register XOR the final XOR,
// so the register starts at 0xFF: CRC-8 SAE J1850, the same arithmetic as the Chrysler checksum.
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

std::uint8_t nissan_checksum(std::span<const std::uint8_t> payload);

}  // namespace meter::controller
