// The E2E checks of every protected message on the controller's inputs: resolved from the map
// file's [e2e MESSAGE] sections (and, with [e2e] detect = true, from the DBCs' conventions), a
// counter state and counts per message. A frame that fails is refused before it is decoded, so
// the signals it carries keep aging and time out as if it never came.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "meter/controller/e2e/e2e_config.hpp"
#include "meter/controller/e2e/e2e_message.hpp"
#include "meter/controller/input/bus_health.hpp"

namespace meter::controller {

struct InputDbc;
struct E2eDetection;
class Database;

struct E2eMessageStats {
  std::uint64_t checked = 0, used = 0;
  std::uint64_t checksum_failed = 0, short_frames = 0;
  std::uint64_t repeated = 0, wrong_sequence = 0, syncing = 0;
  std::uint64_t skips = 0, lost = 0;  // tolerated counter jumps, and the frames they say were lost
  std::uint64_t refused() const { return checked - used; }
};

class E2eGuard {
 public:
  struct Entry {
    E2eMessage message;
    CounterState state;
    E2eMessageStats stats;
  };

  E2eGuard() = default;
  explicit E2eGuard(const E2eSettings& settings) : ratio_(settings.mismatch_ratio), min_frames_(settings.mismatch_min_frames) {}

  void add(E2eMessage message);
  bool empty() const { return entries_.empty(); }
  // The entry protecting m, or -1.
  int find(const DbcMessage* m) const;
  // Checks one frame of entry i, counting the result.
  FrameCheck check(std::size_t i, std::uint32_t id, std::span<const std::uint8_t> payload);
  // True when m is unprotected or the frame passes its checks.
  bool accept(const DbcMessage* m, std::uint32_t id, std::span<const std::uint8_t> payload) {
    const int i = find(m);
    return i < 0 || check(static_cast<std::size_t>(i), id, payload).usable;
  }
  const std::vector<Entry>& entries() const { return entries_; }
  // Nearly every frame refused, over enough frames: the configuration does not fit the sender.
  bool likely_mismatch(const Entry& e) const;

 private:
  double ratio_ = 0.9;
  unsigned min_frames_ = 20;
  std::vector<Entry> entries_;
  // (message, entry index) sorted by message: a few protected messages, looked up on every frame.
  std::vector<std::pair<const DbcMessage*, std::size_t>> by_message_;
};

// The guard for a mapping's E2E settings over the inputs' DBCs: each [e2e MESSAGE] resolved
// ("Message" against the one DBC that defines it, "INPUT.Message" against that input's), then,
// with detect, what each DBC's conventions identify for messages not configured. Throws
// MappingError (file, line) naming what does not resolve.
E2eGuard build_e2e_guard(std::span<const InputDbc> inputs, const E2eSettings& settings, const std::string& map_file);

// Adds what a DBC's conventions identify (`detection`, detect_e2e of input `input`'s `db`) for the
// messages not configured before.
void add_detected_e2e(E2eGuard& guard, const Database& db, int input, const E2eDetection& detection);

// The counts per message, for the bus health and --stats, written into `health` in place: sized
// and named when the guard's messages change, else only the counts rewritten (the run loop's
// every tick allocates nothing).
void update_e2e_health(const E2eGuard& guard, std::vector<E2eHealth>& health);

}  // namespace meter::controller
