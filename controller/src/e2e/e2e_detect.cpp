#include "meter/controller/e2e/e2e_detect.hpp"

#include <cstdio>
#include <stdexcept>

#include "meter/controller/e2e/e2e_message.hpp"
#include "meter/protocol/ascii_case.hpp"

namespace meter::controller {
namespace {

struct Make {
  const char* prefix;  // of the DBC's file name, lower case
  const char* name;
  ChecksumKind checksum;
};
// Longest prefixes first: subaru_global before subaru, hyundai_canfd before hyundai.
constexpr Make kMakes[] = {
    {"subaru_global", "Subaru (global platform)", ChecksumKind::Subaru},
    {"subaru_", "Subaru (pre-global platform)", ChecksumKind::SubaruPreglobal},
    {"hyundai_canfd", "Hyundai/Kia (CAN FD)", ChecksumKind::HyundaiCanFd},
    {"hyundai_", "Hyundai/Kia", ChecksumKind::Hyundai},
    {"kia_", "Hyundai/Kia", ChecksumKind::Hyundai},
    {"vw_mqb", "Volkswagen MQB", ChecksumKind::VwMqb},
    {"toyota_", "Toyota", ChecksumKind::Toyota},
    {"lexus_", "Toyota", ChecksumKind::Toyota},
    {"honda_", "Honda", ChecksumKind::Honda},
    {"acura_", "Honda", ChecksumKind::Honda},
    {"chrysler_", "Chrysler/FCA", ChecksumKind::Chrysler},
    {"nissan_", "Nissan", ChecksumKind::Nissan},
    {"mazda_", "Mazda", ChecksumKind::Mazda},
    {"tesla_", "Tesla", ChecksumKind::Tesla},
};

// opendbc's Tesla DBCs name a message's checksum and counter after it: DAS_controlChecksum,
// DAS_controlCounter. The first signal whose name ends so; empty when none does.
std::string named_with_suffix(const DbcMessage& m, std::string_view suffix) {
  for (const DbcSignal& s : m.signals)
    if (s.name.size() > suffix.size() && s.name.ends_with(suffix)) return s.name;
  return "";
}

std::string hex_id(const DbcMessage& m) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%X", m.id);
  return b;
}

}  // namespace

E2eDetection detect_e2e(const Database& db) {
  E2eDetection d;
  const std::string file = protocol::ascii_lowercase(std::string_view(db.file).substr(db.file.find_last_of('/') + 1));
  for (const Make& mk : kMakes)
    if (file.starts_with(mk.prefix)) {
      d.make = mk.name;
      d.checksum = mk.checksum;
      break;
    }
  for (const DbcMessage& m : db.messages) {
    E2eSpec spec;
    spec.message = m.name;
    spec.checksum = d.checksum;
    if (d.checksum == ChecksumKind::Tesla && checksum_signal_of(m) < 0 && counter_signal_of(m) < 0) {
      spec.checksum_signal = named_with_suffix(m, "Checksum");
      spec.counter_signal = named_with_suffix(m, "Counter");
      if (spec.checksum_signal.empty() && spec.counter_signal.empty()) continue;
      if (spec.checksum_signal.empty()) spec.checksum = ChecksumKind::None;
    }
    E2eMessage e;
    try {
      e = resolve_e2e(spec, m);
    } catch (const std::invalid_argument& why) {
      // No checksum signal, or one where the make's algorithm does not write it: the counter alone.
      spec.checksum = ChecksumKind::None;
      try {
        e = resolve_e2e(spec, m);
      } catch (const std::invalid_argument&) {
        continue;  // neither: nothing to check
      }
      if (d.checksum != ChecksumKind::None && checksum_signal_of(m) >= 0)
        d.notes.push_back(m.name + " (" + hex_id(m) + "): counter only; checksum left out: " + why.what());
    }
    spec = e.spec;
    spec.origin = "detected in " + file + (d.make.empty() ? "" : " (" + d.make + ")");
    const std::string what = spec.checksum == ChecksumKind::None ? "counter " : std::string(to_string(spec.checksum)) + " checksum in " +
        m.signals[static_cast<std::size_t>(e.checksum_signal)].name + (e.counter_signal >= 0 ? ", counter " : "");
    const std::string counter = e.counter_signal >= 0 ? m.signals[static_cast<std::size_t>(e.counter_signal)].name + " (" +
        std::to_string(m.signals[static_cast<std::size_t>(e.counter_signal)].length) + " bits)" : "";
    d.notes.push_back(m.name + " (" + hex_id(m) + "): " + what + counter);
    d.messages.push_back(std::move(spec));
  }
  return d;
}

}  // namespace meter::controller
