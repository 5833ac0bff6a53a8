// Value rules the encoder and the decoder share.
#pragma once

#include <cstdint>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol::detail {

inline bool valid_status(std::uint8_t s) { return s <= static_cast<std::uint8_t>(SignalStatus::NotAvailable); }

}  // namespace meter::protocol::detail
