#include "meter/controller/e2e/autosar_profile05.hpp"

#include "meter/controller/e2e/crc16_ccitt.hpp"

namespace meter::controller {

std::uint16_t autosar_profile05_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id) {
  if (crc_byte > payload.size()) crc_byte = payload.size();
  std::uint16_t reg = crc16_ccitt_update(0xFFFF, payload.first(crc_byte));
  if (crc_byte + 2 < payload.size()) reg = crc16_ccitt_update(reg, payload.subspan(crc_byte + 2));
  const std::uint8_t id[2] = {static_cast<std::uint8_t>(data_id & 0xFF), static_cast<std::uint8_t>(data_id >> 8)};
  return crc16_ccitt_update(reg, id);
}

}  // namespace meter::controller
