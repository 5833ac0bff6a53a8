#include "meter/controller/e2e/autosar_profile02.hpp"

#include "meter/controller/e2e/crc8h2f.hpp"

namespace meter::controller {

std::uint8_t autosar_profile02_crc(std::span<const std::uint8_t> payload, const DataIdList& data_ids, unsigned counter) {
  std::uint8_t reg = 0xFF;
  if (payload.size() > 1) reg = crc8h2f_update(reg, payload.subspan(1));
  const std::uint8_t id = data_ids[counter & 0x0F];
  reg = crc8h2f_update(reg, std::span<const std::uint8_t>(&id, 1));
  return static_cast<std::uint8_t>(reg ^ 0xFF);
}

}  // namespace meter::controller
