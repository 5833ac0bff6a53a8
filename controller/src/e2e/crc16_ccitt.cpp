#include "meter/controller/e2e/crc16_ccitt.hpp"

#include "crc_table.hpp"

namespace meter::controller {
namespace {
constexpr auto kCcittTable = crc_detail::msb_first_table<std::uint16_t, 0x1021>();
}

std::uint16_t crc16_ccitt_update(std::uint16_t reg, std::span<const std::uint8_t> data) {
  for (std::uint8_t b : data) reg = static_cast<std::uint16_t>((reg << 8) ^ kCcittTable[((reg >> 8) ^ b) & 0xFF]);
  return reg;
}

std::uint16_t crc16_ccitt_false(std::span<const std::uint8_t> data) { return crc16_ccitt_update(0xFFFF, data); }

}  // namespace meter::controller
