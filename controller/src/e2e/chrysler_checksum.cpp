#include "meter/controller/e2e/chrysler_checksum.hpp"

#include "meter/controller/e2e/crc8_sae_j1850.hpp"

namespace meter::controller {

std::uint8_t chrysler_checksum(std::span<const std::uint8_t> payload) {
  return crc8_sae_j1850(payload.empty() ? payload : payload.first(payload.size() - 1));
}

}  // namespace meter::controller
