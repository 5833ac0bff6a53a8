#include "meter/controller/e2e/tesla_checksum.hpp"

namespace meter::controller {

std::uint8_t tesla_checksum(std::uint32_t id, std::span<const std::uint8_t> payload, std::size_t checksum_byte) {
  unsigned sum = (id & 0xFF) + ((id >> 8) & 0xFF);
  for (std::size_t i = 0; i < payload.size(); ++i)
    if (i != checksum_byte) sum += payload[i];
  return static_cast<std::uint8_t>(sum & 0xFF);
}

}  // namespace meter::controller
