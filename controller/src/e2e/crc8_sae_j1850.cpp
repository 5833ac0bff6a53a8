#include "meter/controller/e2e/crc8_sae_j1850.hpp"

#include "crc_table.hpp"

namespace meter::controller {

using J1850 = crc_detail::MsbFirstCrc<std::uint8_t, 0x1D>;

std::uint8_t crc8_sae_j1850_update(std::uint8_t reg, std::span<const std::uint8_t> data) { return J1850::update(reg, data); }

std::uint8_t crc8_sae_j1850(std::span<const std::uint8_t> data) { return static_cast<std::uint8_t>(J1850::update(0xFF, data) ^ 0xFF); }

}  // namespace meter::controller
