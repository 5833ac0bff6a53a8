// Payload encoders and decoders, one per message type (HELLO, SNAPSHOT/DELTA update lists,
// HEARTBEAT, STATUS, CLOSE). The frame codec (frame_codec.cpp) wraps them in header and CRC.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "byte_io.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

inline bool valid_status(std::uint8_t s) { return s <= static_cast<std::uint8_t>(SignalStatus::NotAvailable); }

// Writes the payload of `m`; throws std::invalid_argument / std::length_error for a value the
// format cannot carry, so the encoder never produces a frame the decoder rejects.
void encode_payload(const Message& m, Writer& w);

// Parses the payload of a frame of (known) `type`; false with `detail` set when it breaks the format.
bool decode_payload(std::uint8_t type, std::span<const std::uint8_t> payload, Message& out, std::string& detail);

}  // namespace meter::protocol::detail
