// What the map file (or detection from a DBC's conventions) says about one protected message:
// which checksum algorithm guards it, in which signals the checksum and the alive counter sit, its
// data id, and the counter's tolerances. Plain data; resolved against the DBC in e2e_message.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/e2e/autosar_profile01.hpp"
#include "meter/controller/e2e/counter_check.hpp"

namespace meter::controller {

enum class ChecksumKind : std::uint8_t {
  None,             // counter only
  Toyota,
  Honda,
  VwMqb,
  Hyundai,          // classic CAN nibble sum
  HyundaiCanFd,
  Subaru,           // global platform
  SubaruPreglobal,
  Chrysler,
  Nissan,
  Mazda,
  Tesla,
  Profile01,
  Profile02,
  Profile05,
  Profile11,
};
// The map file's names: "none", "toyota", "honda", "vw-mqb", "hyundai", "hyundai-canfd", "subaru",
// "subaru-preglobal", "chrysler", "nissan", "mazda", "tesla", "autosar-p01", "autosar-p02",
// "autosar-p05", "autosar-p11".
std::string_view to_string(ChecksumKind kind);
std::optional<ChecksumKind> checksum_kind_named(std::string_view name);
std::string checksum_kind_names();  // the list above, for errors and help

struct E2eSpec {
  std::string message;  // "Message" or "INPUT.Message"
  int line = 0;         // where the map file configures it (0: detected)
  std::string origin;   // "map file line N" or what detection saw
  ChecksumKind checksum = ChecksumKind::None;
  std::string checksum_signal;  // empty: the message's signal named like a checksum
  std::string counter_signal;   // empty: the message's signal named like a counter
  bool counter = true;          // false: no counter check ('counter_signal = none')
  std::uint16_t data_id = 0;    // profiles 1, 5, 11
  DataIdMode data_id_mode = DataIdMode::Both;
  std::vector<std::uint8_t> data_ids;  // profile 2 (16 entries); for vw-mqb, replaces the built-in list
  CounterTolerance tolerance;
};

struct E2eSettings {
  bool detect = false;  // also check what the DBC's conventions identify ([e2e] detect = true)
  // A message whose refused share of its checked frames reaches mismatch_ratio after at least
  // mismatch_min_frames frames is reported as a likely configuration mismatch.
  double mismatch_ratio = 0.9;
  unsigned mismatch_min_frames = 20;
  std::vector<E2eSpec> messages;
};

}  // namespace meter::controller
