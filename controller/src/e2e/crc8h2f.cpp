#include "meter/controller/e2e/crc8h2f.hpp"

#include "crc_table.hpp"

namespace meter::controller {

// The 0x2F polynomial ("8H2F" in the AUTOSAR CRC library's naming).
std::uint8_t crc8h2f_update(std::uint8_t reg, std::span<const std::uint8_t> data) {
  return crc_detail::MsbFirstCrc<std::uint8_t, 0x2F>::update(reg, data);
}

std::uint8_t crc8h2f(std::span<const std::uint8_t> data) { return static_cast<std::uint8_t>(crc8h2f_update(0xFF, data) ^ 0xFF); }

}  // namespace meter::controller
