#include "meter/controller/e2e/counter_check.hpp"

namespace meter::controller {

std::string_view to_string(CounterStatus s) {
  switch (s) {
    case CounterStatus::Initial: return "initial";
    case CounterStatus::Ok: return "ok";
    case CounterStatus::Skipped: return "skipped";
    case CounterStatus::Repeated: return "repeated";
    case CounterStatus::WrongSequence: return "wrong-sequence";
    case CounterStatus::Syncing: return "syncing";
  }
  return "unknown";
}

CounterResult check_counter(CounterState& st, std::uint32_t counter, std::uint32_t modulus, const CounterTolerance& tol) {
  if (modulus == 0) modulus = 1;
  counter %= modulus;
  if (!st.seen) {
    st = CounterState{true, counter, 0, 0};
    return {CounterStatus::Initial, 0};
  }
  const std::uint32_t step = (counter + modulus - st.last) % modulus;
  if (step == 0) {
    if (++st.repeats > tol.max_repeated) st.sync_left = tol.sync_frames;
    return {CounterStatus::Repeated, 0};
  }
  st.repeats = 0;
  st.last = counter;
  if (step > tol.max_delta) {
    st.sync_left = tol.sync_frames;
    return {CounterStatus::WrongSequence, 0};
  }
  if (st.sync_left > 0) {
    --st.sync_left;
    return {CounterStatus::Syncing, 0};
  }
  if (step == 1) return {CounterStatus::Ok, 0};
  return {CounterStatus::Skipped, step - 1};
}

}  // namespace meter::controller
