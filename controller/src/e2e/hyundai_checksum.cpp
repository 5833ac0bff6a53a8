#include "meter/controller/e2e/hyundai_checksum.hpp"

namespace meter::controller {

std::uint8_t hyundai_checksum(std::span<const std::uint8_t> payload, unsigned checksum_bit) {
  unsigned sum = 0;
  for (std::size_t i = 0; i < payload.size(); ++i) {
    for (unsigned half = 0; half < 2; ++half) {
      if (i * 8 + half * 4 == checksum_bit) continue;
      sum += (payload[i] >> (half * 4)) & 0x0F;
    }
  }
  return static_cast<std::uint8_t>((16 - sum % 16) % 16);
}

}  // namespace meter::controller
