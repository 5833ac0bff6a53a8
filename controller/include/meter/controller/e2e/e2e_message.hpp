// One protected message resolved against its DBC: where its checksum and counter sit, and the
// check of one received frame (checksum, then counter): the per-message check result that says
// whether the frame may be used. Pure: no clock, no I/O.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/autosar_profile02.hpp"
#include "meter/controller/e2e/counter_check.hpp"
#include "meter/controller/e2e/e2e_config.hpp"

namespace meter::controller {

struct E2eMessage {
  const DbcMessage* message = nullptr;
  int input = 0;  // the input (bus) whose frames carry it
  E2eSpec spec;
  int checksum_signal = -1, counter_signal = -1;  // indices into message->signals, -1 = none
  std::size_t checksum_byte = 0;  // the checksum's (lowest) byte
  unsigned checksum_bit = 0;      // the checksum's lowest little-endian bit number (byte * 8 + bit)
  std::uint32_t counter_modulus = 0;
  DataIdList data_ids{};  // profile 2 and vw-mqb
};

// The message's signal named like a checksum (CHECKSUM, CRC, CHKSUM in any case) or like an alive
// counter (COUNTER, CTR, ALIVE_COUNTER, ROLLING_COUNTER); -1 when it has none.
int checksum_signal_of(const DbcMessage& m);
int counter_signal_of(const DbcMessage& m);

// Resolves spec against message m: finds the checksum and counter signals (named, or the one
// named CHECKSUM/CRC/CHKSUM and COUNTER/CTR in any case) and checks that the checksum sits where
// its algorithm writes it. Throws std::invalid_argument naming the message, the signal and what
// was expected.
E2eMessage resolve_e2e(const E2eSpec& spec, const DbcMessage& m, int input = 0);

enum class ChecksumStatus : std::uint8_t { Ok, Bad, NotChecked, ShortFrame };
std::string_view to_string(ChecksumStatus status);  // "ok", "bad", "none", "short-frame"

struct FrameCheck {
  ChecksumStatus checksum = ChecksumStatus::NotChecked;
  std::uint32_t received = 0, expected = 0;  // the checksum in the frame and the one computed
  bool has_counter = false;
  std::uint32_t counter = 0;
  CounterResult counter_result;
  bool usable = false;  // checksum good (or none) and the counter says new data
};

// The checksum the sender should have written for this payload (counter: the frame's counter
// value, for algorithms that mix it in); nullopt when the algorithm cannot say (a length it does
// not define).
std::optional<std::uint32_t> expected_checksum(const E2eMessage& m, std::uint32_t id, std::span<const std::uint8_t> payload,
                                               std::uint32_t counter);
// Checks one frame of m: the checksum first; only a frame whose checksum is good moves the counter
// state on.
FrameCheck check_frame(const E2eMessage& m, CounterState& state, std::uint32_t id, std::span<const std::uint8_t> payload);

}  // namespace meter::controller
