#include "meter/controller/e2e/autosar_profile01.hpp"

#include "meter/controller/e2e/crc8_sae_j1850.hpp"

namespace meter::controller {

std::uint8_t autosar_profile01_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id,
                                   DataIdMode mode, unsigned counter) {
  const std::uint8_t low = static_cast<std::uint8_t>(data_id & 0xFF), high = static_cast<std::uint8_t>(data_id >> 8);
  std::uint8_t id[2] = {low, high};
  std::size_t id_len = 2;
  switch (mode) {
    case DataIdMode::Both: break;
    case DataIdMode::Alternating: id[0] = (counter % 2 == 0) ? low : high, id_len = 1; break;
    case DataIdMode::Low: id_len = 1; break;
    case DataIdMode::Nibble: id[1] = 0; break;
  }
  std::uint8_t reg = crc8_sae_j1850_update(0x00, std::span<const std::uint8_t>(id, id_len));
  if (crc_byte > payload.size()) crc_byte = payload.size();
  reg = crc8_sae_j1850_update(reg, payload.first(crc_byte));
  if (crc_byte < payload.size()) reg = crc8_sae_j1850_update(reg, payload.subspan(crc_byte + 1));
  return reg;
}

}  // namespace meter::controller
