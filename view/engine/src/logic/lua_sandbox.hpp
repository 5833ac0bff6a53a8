// One scene script's Lua state, sandboxed: only the base (without dofile, loadfile, load,
// collectgarbage, print, warn), table, string (without dump and the backtracking pattern
// functions find, match, gmatch, gsub), math and utf8 libraries; text chunks only; a cap on the
// state's live memory and on the bytes one run allocates (custom lua_Alloc), an instruction
// limit per run (count hook), and Lua's own C-stack and Lua-stack limits against deep recursion.
// Every call into the state is protected: nothing a script does can end the process.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "meter/bridge/scene_scripts.hpp"
#include "meter/protocol/catalog.hpp"

struct lua_State;

namespace meter::engine::logic {

// An input as the script sees it: IN.<name>.value (nil unless valid; a string for text signals,
// an integer for enum and telltale signals' whole values, else a float), IN.<name>.status
// ("valid", "timed-out", "invalid", "not-available"), IN.<name>.valid.
struct InputValue {
  double value = 0.0;
  std::string text;
  bool is_text = false;
  bool is_integer = false;
  protocol::SignalStatus status = protocol::SignalStatus::NotAvailable;
};

// An output as the script left it in OUT.<name> after a run: `set` false when it is nil.
struct OutputValue {
  bool set = false;
  std::array<double, 4> numbers{0, 0, 0, 1};
  bool visible = false;
  std::string text;
  bool operator==(const OutputValue&) const = default;
};

class LuaSandbox {
 public:
  // Creates the state and runs the chunk once (it defines `function run(IN, OUT)` and any state it
  // keeps between runs). A failure leaves the sandbox broken(), with the message in error().
  explicit LuaSandbox(const bridge::Script& script);
  ~LuaSandbox();
  LuaSandbox(const LuaSandbox&) = delete;
  LuaSandbox& operator=(const LuaSandbox&) = delete;

  // Sets IN from `inputs` (one per script input, in order), calls run(IN, OUT) and reads every
  // declared output into `outputs` (one per script output). False on an error or a limit, with
  // error() naming the script and the line ("shift_light:7: attempt to compare nil with number").
  bool run(std::span<const InputValue> inputs, std::vector<OutputValue>& outputs);

  bool broken() const { return L_ == nullptr || run_ref_ < 0; }
  const std::string& error() const { return error_; }
  std::size_t memory() const { return alloc_.used; }
  std::size_t memory_peak() const { return alloc_.peak; }

  // Allocator bookkeeping (public for the allocator and hooks in the .cpp).
  struct Alloc {
    std::size_t used = 0, peak = 0, limit = 0;
    std::size_t run_bytes = 0, run_limit = 0;  // grown during the current run
    bool in_run = false;
    bool refused = false;  // a limit was hit this run (sticky until the run ends)
  };
  struct Run {
    std::span<const InputValue> inputs;
    std::vector<OutputValue>* outputs = nullptr;
    long long instructions = 0;     // counted by the hook, in steps of kHookStep
    bool instruction_limit = false;  // hit this run (sticky: every later instruction errors)
    int line = -1;                  // innermost Lua line last seen (hook, message handler)
  };
  static constexpr int kHookStep = 1000;

  const bridge::Script& script() const { return script_; }
  Alloc& alloc() { return alloc_; }
  Run& current() { return run_; }

 private:
  static int protected_setup(lua_State* L);  // inside lua_pcall: libraries, IN, OUT, the chunk
  static int protected_run(lua_State* L);    // inside lua_pcall: IN, run(IN, OUT), OUT
  // Runs `body` under lua_pcall with the message handler and this run's limits; false on failure.
  bool call_protected(int (*body)(lua_State*));
  std::string describe_failure(int rc, const char* message) const;

  const bridge::Script& script_;
  const std::string chunk_name_;  // "=<name>": Lua's messages read "<name>:<line>: ..."
  Alloc alloc_;
  Run run_;
  lua_State* L_ = nullptr;
  int run_ref_ = -1, in_ref_ = -1, out_ref_ = -1;
  std::string error_;
};

}  // namespace meter::engine::logic
