// Fuzzes the E2E configuration the way meter-controller uses it: the first byte picks the DBC's
// file name (which says the make detection assumes), the rest is a map file whose [e2e] sections
// are resolved against a DBC carrying checksums and counters in every layout the algorithms use;
// then a second of frames built from the input's bytes goes through the model's checks. Every
// rejection must be an exception naming the file and line ("fuzz.map:N: ..."); the per-message
// counts must add up; no output may be NaN.
#include <array>
#include <cstdlib>
#include <optional>
#include <string>

#include "fixed_vehicle.hpp"
#include "meter/controller/dbc/parse.hpp"
#include "meter/controller/model/model.hpp"

using namespace meter::controller;

namespace {

// The checksum where each make writes it: the last byte, byte 0 with the counter in bits 8..11,
// the last byte's low nibble, two bytes little-endian, a byte in the middle (Motorola), an
// extended id, and a message with neither.
const char* kDbc =
    "BO_ 16 LAST: 8 ECU\n SG_ VALUE : 0|16@1+ (0.01,0) [0|250] \"\" ICL\n SG_ COUNTER : 52|4@1+ (1,0) [0|15] \"\" ICL\n"
    " SG_ CHECKSUM : 56|8@1+ (1,0) [0|255] \"\" ICL\n"
    "BO_ 32 FIRST: 8 ECU\n SG_ CHECKSUM : 0|8@1+ (1,0) [0|255] \"\" ICL\n SG_ COUNTER : 8|4@1+ (1,0) [0|15] \"\" ICL\n"
    " SG_ VALUE : 16|16@1+ (0.01,0) [0|250] \"\" ICL\n"
    "BO_ 48 NIBBLE: 8 ECU\n SG_ VALUE : 0|8@1+ (1,0) [0|255] \"\" ICL\n SG_ CHECKSUM : 56|4@1+ (1,0) [0|15] \"\" ICL\n"
    " SG_ COUNTER : 60|2@1+ (1,0) [0|3] \"\" ICL\n"
    "BO_ 64 WIDE: 16 ECU\n SG_ CHECKSUM : 0|16@1+ (1,0) [0|65535] \"\" ICL\n SG_ COUNTER : 16|8@1+ (1,0) [0|255] \"\" ICL\n"
    " SG_ VALUE : 24|8@1+ (1,0) [0|255] \"\" ICL\n"
    "BO_ 80 MIDDLE: 8 ECU\n SG_ COUNTER : 27|3@0+ (1,0) [0|7] \"\" ICL\n SG_ Checksum : 39|8@0+ (1,0) [0|255] \"\" ICL\n"
    " SG_ VALUE : 48|8@1+ (1,0) [0|255] \"\" ICL\n"
    "BO_ 2147483744 EXT: 8 ECU\n SG_ CHECKSUM : 56|4@1+ (1,0) [0|15] \"\" ICL\n SG_ COUNTER : 60|2@1+ (1,0) [0|3] \"\" ICL\n"
    "BO_ 112 PLAIN: 8 ECU\n SG_ X : 0|8@1+ (1,0) [0|255] \"\" ICL\n";

constexpr const char* kNames[] = {"toyota_f.dbc",        "honda_f.dbc",   "vw_mqb_f.dbc",  "subaru_global_f.dbc",
                                  "subaru_f.dbc",        "hyundai_f.dbc", "hyundai_canfd_f.dbc", "chrysler_f.dbc",
                                  "nissan_f.dbc",        "mazda_f.dbc",   "tesla_f.dbc",   "other.dbc"};
constexpr std::size_t kNameCount = sizeof kNames / sizeof kNames[0];

const Database& dbc_named(std::size_t i) {
  static std::array<std::optional<Database>, kNameCount> dbs;
  if (!dbs[i]) dbs[i] = parse_dbc(kDbc, kNames[i]);
  return *dbs[i];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const Database& db = dbc_named(data[0] % kNameCount);
  ++data, --size;
  std::optional<Model> model;
  if (!fuzz::model_for_map(model, db, fuzz::as_text(data, size))) return 0;
  // A second of frames, every seventh a byte short (a short frame is refused, never decoded).
  model->start(0);
  const std::string_view bytes = fuzz::as_text(data, size);
  for (std::int64_t tick = 0; tick < 100; ++tick) {
    const CanFrame f = fuzz::fuzz_frame(db, tick, bytes, 13, 7);
    model->on_frame(f);
    model->update(f.timestamp_ns);
    fuzz::require_finite_outputs(*model);
  }
  std::uint64_t refused = 0;
  for (const auto& e : model->e2e().entries()) {
    const E2eMessageStats& s = e.stats;
    if (s.used > s.checked || s.checksum_failed + s.short_frames + s.repeated + s.wrong_sequence + s.syncing != s.refused())
      std::abort();  // every refused frame has exactly one reason
    refused += s.refused();
  }
  if (refused != model->stats().frames_refused) std::abort();
  return 0;
}
