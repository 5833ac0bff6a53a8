#include "meter/controller/e2e/subaru_preglobal_checksum.hpp"

namespace meter::controller {

std::uint8_t subaru_preglobal_checksum(std::span<const std::uint8_t> payload, std::size_t checksum_byte) {
  unsigned sum = 0;
  for (std::size_t i = 0; i < payload.size(); ++i)
    if (i != checksum_byte) sum += payload[i];
  return static_cast<std::uint8_t>(sum & 0xFF);
}

}  // namespace meter::controller
