#include "meter/controller/e2e/hyundai_canfd_checksum.hpp"

#include "meter/controller/e2e/crc16_ccitt.hpp"

namespace meter::controller {

std::optional<std::uint16_t> hyundai_canfd_checksum(std::uint32_t id, std::span<const std::uint8_t> payload) {
  std::uint16_t final_xor = 0;
  switch (payload.size()) {
    case 8: final_xor = 0x5F29; break;
    case 16: final_xor = 0x041D; break;
    case 24: final_xor = 0x819D; break;
    case 32: final_xor = 0x9F5B; break;
    default: return std::nullopt;
  }
  std::uint16_t reg = crc16_ccitt_update(0, payload.subspan(2));
  const std::uint8_t address[2] = {static_cast<std::uint8_t>(id & 0xFF), static_cast<std::uint8_t>((id >> 8) & 0xFF)};
  reg = crc16_ccitt_update(reg, address);
  return static_cast<std::uint16_t>(reg ^ final_xor);
}

}  // namespace meter::controller
