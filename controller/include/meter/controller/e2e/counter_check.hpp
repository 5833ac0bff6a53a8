// The alive counter of a protected message, judged as the AUTOSAR E2E state machine does
// (E2E_P01Check / E2E_P02Check): the step from the last accepted counter decides whether a frame is
// new (step 1), new after lost frames (step 2..max_delta), a repetition (step 0: a stale sender,
// or a replayed frame) or out of sequence (beyond max_delta); after an out-of-sequence frame, and
// after too many repetitions in a row, sync_frames frames in sequence are needed before frames are
// used again. Pure: a state, a counter value, a result.
#pragma once

#include <cstdint>
#include <string_view>

namespace meter::controller {

struct CounterTolerance {
  unsigned max_delta = 2;     // largest accepted step: 1 = no lost frame tolerated (MaxDeltaCounter)
  unsigned sync_frames = 0;   // frames in sequence needed after a wrong sequence (SyncCounterInit)
  unsigned max_repeated = 1;  // repetitions in a row tolerated before resynchronising (MaxNoNewOrRepeatedData)
  bool operator==(const CounterTolerance&) const = default;
};

enum class CounterStatus : std::uint8_t {
  Initial,        // the first frame: nothing to compare with, used
  Ok,             // step 1
  Skipped,        // step 2..max_delta: frames were lost, this one is used
  Repeated,       // step 0: not new, not used
  WrongSequence,  // step beyond max_delta: not used, resynchronising
  Syncing,        // in sequence again, but fewer than sync_frames so far: not used
};
std::string_view to_string(CounterStatus status);  // "initial", "ok", "skipped", "repeated", "wrong-sequence", "syncing"
inline bool counter_usable(CounterStatus s) {
  return s == CounterStatus::Initial || s == CounterStatus::Ok || s == CounterStatus::Skipped;
}

struct CounterState {
  bool seen = false;
  std::uint32_t last = 0;   // the last counter value accepted as a step
  unsigned sync_left = 0;   // frames in sequence still needed
  unsigned repeats = 0;     // repetitions in a row
};

struct CounterResult {
  CounterStatus status = CounterStatus::Initial;
  std::uint32_t lost = 0;  // frames lost before this one (Skipped: step - 1)
};

// modulus: how many counter values there are (2^bits, or 15 for profile 1's 0..14).
CounterResult check_counter(CounterState& state, std::uint32_t counter, std::uint32_t modulus, const CounterTolerance& tolerance);

}  // namespace meter::controller
