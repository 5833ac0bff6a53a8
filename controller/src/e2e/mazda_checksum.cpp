#include "meter/controller/e2e/mazda_checksum.hpp"

namespace meter::controller {

std::uint8_t mazda_checksum(std::span<const std::uint8_t> payload) {
  int c = 249;
  if (!payload.empty()) c -= (payload[0] >> 4) + (payload[0] & 0x0F);
  for (std::size_t i = 1; i + 1 < payload.size(); ++i) c -= payload[i];
  return static_cast<std::uint8_t>(c & 0xFF);
}

}  // namespace meter::controller
