#include "meter/controller/e2e/crc8h2f.hpp"

#include "crc_table.hpp"

namespace meter::controller {
namespace {
constexpr auto kH2fTable = crc_detail::msb_first_table<std::uint8_t, 0x2F>();
}

std::uint8_t crc8h2f_update(std::uint8_t reg, std::span<const std::uint8_t> data) {
  for (std::uint8_t b : data) reg = kH2fTable[reg ^ b];
  return reg;
}

std::uint8_t crc8h2f(std::span<const std::uint8_t> data) {
  return static_cast<std::uint8_t>(crc8h2f_update(0xFF, data) ^ 0xFF);
}

}  // namespace meter::controller
