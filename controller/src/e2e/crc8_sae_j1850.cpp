#include "meter/controller/e2e/crc8_sae_j1850.hpp"

#include "crc_table.hpp"

namespace meter::controller {
namespace {
constexpr auto kJ1850Table = crc_detail::msb_first_table<std::uint8_t, 0x1D>();
}

std::uint8_t crc8_sae_j1850_update(std::uint8_t reg, std::span<const std::uint8_t> data) {
  for (std::uint8_t b : data) reg = kJ1850Table[reg ^ b];
  return reg;
}

std::uint8_t crc8_sae_j1850(std::span<const std::uint8_t> data) {
  return static_cast<std::uint8_t>(crc8_sae_j1850_update(0xFF, data) ^ 0xFF);
}

}  // namespace meter::controller
