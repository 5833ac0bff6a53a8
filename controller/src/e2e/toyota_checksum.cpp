#include "meter/controller/e2e/toyota_checksum.hpp"

namespace meter::controller {

std::uint8_t toyota_checksum(std::uint32_t id, std::span<const std::uint8_t> payload) {
  unsigned sum = static_cast<unsigned>(payload.size());
  for (std::uint32_t a = id; a != 0; a >>= 8) sum += a & 0xFF;
  for (std::size_t i = 0; i + 1 < payload.size(); ++i) sum += payload[i];
  return static_cast<std::uint8_t>(sum & 0xFF);
}

}  // namespace meter::controller
