// Volkswagen MQB: AUTOSAR E2E profile 2 (CRC-8H2F in byte 0, counter in bits 8..11) with a data id
// list per message. The lists are those of the messages opendbc documents (vw_mqb_2010.dbc's
// CHECKSUM signals), each cross-checked against frames recorded on the cars.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "meter/controller/e2e/autosar_profile02.hpp"

namespace meter::controller {

// The data id list of an MQB message (11-bit id); nullopt for a message whose list is not known.
std::optional<DataIdList> vw_mqb_data_ids(std::uint32_t id);
// The CRC an MQB sender writes in byte 0; nullopt for a message whose list is not known.
std::optional<std::uint8_t> vw_mqb_checksum(std::uint32_t id, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
