#include "meter/controller/e2e/crc16_ccitt.hpp"

#include "crc_table.hpp"

namespace meter::controller {

std::uint16_t crc16_ccitt_update(std::uint16_t reg, std::span<const std::uint8_t> data) {
  return crc_detail::MsbFirstCrc<std::uint16_t, 0x1021>::update(reg, data);
}

std::uint16_t crc16_ccitt_false(std::span<const std::uint8_t> data) { return crc16_ccitt_update(0xFFFF, data); }

}  // namespace meter::controller
