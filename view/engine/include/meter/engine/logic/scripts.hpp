// Scene scripts at run time (docs/scene-logic.md): one sandboxed Lua state per script, run only
// when one of its inputs changed, its outputs laid over the bindings' outputs each update.
//
// Per update(), for each script:
//   link down        -> its outputs show their failsafe (hold when they have none); it does not run;
//   an input changed -> run(IN, OUT) (counted and timed); on success OUT is taken; on an error or
//                       a limit the script is failed: outputs in failsafe, a rate-limited message
//                       naming script:line; it is tried again at the next input change;
//   otherwise        -> nothing runs; the last outputs stand.
// Then every output that holds a value replaces the bindings' effect on its property.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::engine {

namespace logic {
class LuaSandbox;
struct InputValue;
struct OutputValue;
}  // namespace logic

// What a script has cost and done, for the live loop's log and --info.
struct ScriptStats {
  std::string name;
  std::uint64_t updates = 0;   // update() calls that looked at it
  std::uint64_t runs = 0;      // run(IN, OUT) calls (an input changed, or the link came back)
  std::uint64_t failures = 0;  // runs (or the load) that raised an error or hit a limit
  double total_ms = 0.0, max_ms = 0.0, last_ms = 0.0;  // run time, measured around each run
  std::size_t memory_bytes = 0, memory_peak_bytes = 0;  // the state's live bytes (allocator count)
  bool failed = false;         // outputs in failsafe now (the last run failed)
  std::string last_error;      // "shift_light:7: attempt to compare nil with number"
};

// "shift_light: 312 runs / 9000 updates, 0 failed, 2.1 us mean, 9.8 us max, 24 KiB" (one line).
std::string describe(const ScriptStats& stats);

class ScriptEngine {
 public:
  using Clock = std::chrono::steady_clock;
  // Resolves every output's target against the scene (throws SceneError naming the script and
  // the output) and creates each script's state (a script that does not load is failed from the
  // start, with its message queued). `message_interval`: at most one message per script per
  // interval; the failures in between are counted in the next one.
  explicit ScriptEngine(const Scene& scene, std::chrono::milliseconds message_interval = std::chrono::seconds(10));
  ~ScriptEngine();
  ScriptEngine(const ScriptEngine&) = delete;
  ScriptEngine& operator=(const ScriptEngine&) = delete;

  // Runs the scripts whose inputs changed and lays every script's outputs over `outputs`.
  void update(const protocol::SignalTable& signals, bool link_up, BindingOutputs& outputs);
  // Looks the inputs' signals up again by name (see BindingEvaluator::rebind); returns the missing.
  std::vector<std::string> rebind(const protocol::Catalog& catalog);

  const std::vector<ScriptStats>& stats() const { return stats_; }
  // Messages queued since the last call (failures, recoveries), oldest first.
  std::vector<std::string> take_messages();

 private:
  struct Output;
  struct Entry;
  void run_script(std::size_t i);
  void note(std::size_t i, const std::string& message, bool failure);

  const Scene& scene_;
  std::chrono::milliseconds interval_;
  std::vector<std::unique_ptr<Entry>> entries_;
  std::vector<ScriptStats> stats_;
  std::vector<std::string> messages_;
};

}  // namespace meter::engine
