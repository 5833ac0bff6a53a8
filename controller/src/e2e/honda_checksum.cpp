#include "meter/controller/e2e/honda_checksum.hpp"

namespace meter::controller {

std::uint8_t honda_checksum(std::uint32_t id, bool extended, std::span<const std::uint8_t> payload) {
  int sum = 0;
  for (std::uint32_t a = id; a != 0; a >>= 4) sum += static_cast<int>(a & 0x0F);
  for (std::size_t i = 0; i < payload.size(); ++i) {
    const unsigned b = payload[i];
    sum += static_cast<int>(b >> 4);
    if (i + 1 < payload.size()) sum += static_cast<int>(b & 0x0F);  // the last low nibble is the checksum
  }
  int c = 8 - sum + (extended ? 3 : 0);
  return static_cast<std::uint8_t>(c & 0x0F);
}

}  // namespace meter::controller
