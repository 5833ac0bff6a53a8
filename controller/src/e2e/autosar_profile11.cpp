#include "meter/controller/e2e/autosar_profile11.hpp"

namespace meter::controller {

std::uint8_t autosar_profile11_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id,
                                   DataIdMode mode) {
  return autosar_profile01_crc(payload, crc_byte, data_id, mode, 0);
}

bool autosar_profile11_nibble_ok(std::span<const std::uint8_t> payload, std::uint16_t data_id, DataIdMode mode,
                                 unsigned nibble_bit) {
  if (mode != DataIdMode::Nibble) return true;
  const std::size_t byte = nibble_bit / 8;
  if (byte >= payload.size()) return false;
  const unsigned nibble = (payload[byte] >> (nibble_bit % 8)) & 0x0F;
  return nibble == ((data_id >> 8) & 0x0F);
}

}  // namespace meter::controller
