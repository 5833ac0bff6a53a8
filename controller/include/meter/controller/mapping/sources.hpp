// The mapping's sources: every "Message.Signal", "INPUT.Message.Signal" or "modbus.NAME" a mapping
// names, resolved once against the DBC of the input (bus) that carries it, with the newest value
// received for each. Frames go in and are decoded (only
// the messages the mapping uses); the readings come out as plain data for mapping/apply.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/can_frame.hpp"
#include "meter/controller/mapping/apply.hpp"
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller {

inline bool is_modbus_source(std::string_view key) { return key.rfind("modbus.", 0) == 0; }

// One input (bus) as the mapping sees it: its --input name (empty for a single unnamed input) and
// its DBC (null when it has none, e.g. a Modbus input).
struct InputDbc {
  std::string name;
  const Database* db = nullptr;
};

struct DbcSource {
  const DbcMessage* message = nullptr;
  int signal = -1;  // index into message->signals
  const DbcSignal& dbc_signal() const { return message->signals[static_cast<std::size_t>(signal)]; }
};
// Resolves "Message.Signal" against db. Throws MappingError (file, line) naming what is missing:
// no DBC at all, no such message, or no such signal in it.
DbcSource resolve_dbc_source(const Database* db, const std::string& key, const std::string& file, int line);

// A DBC source and the input whose frames carry it.
struct InputSource {
  int input = 0;  // index into the inputs
  DbcSource dbc;
};
// Resolves "INPUT.Message.Signal" against that input's DBC, and "Message.Signal" against the only
// DBC there is or, with several, against the one input whose DBC has that message. Throws
// MappingError (file, line) naming what is wrong: an unknown input, an input without a DBC, a
// message that several inputs' DBCs define (ambiguous: the source must name its input), or a
// message or signal that does not exist.
InputSource resolve_input_source(std::span<const InputDbc> inputs, const std::string& key, const std::string& file,
                                 int line);

struct Source {
  std::string key;
  int input = 0;                // the input whose frames carry it (DBC sources)
  DbcSource dbc;                // message null for Modbus sources
  std::optional<int> cycle_ms;  // DBC cycle time, or the Modbus poll period
  SourceReading reading;
  std::uint64_t raw = 0;       // raw bits of the newest DBC value (wheel-pulse counters)
  std::uint64_t rx_count = 0;  // values received so far
};

// What a frame meant to the sources. Refused: a protected message whose end-to-end check failed
// (e2e/e2e_guard.hpp): not decoded, its signals keep aging.
enum class FrameUse : std::uint8_t { ErrorFrame, Ignored, UnknownId, Unused, Mapped, Refused };

class E2eGuard;

class SourceTable {
 public:
  // db may be null (Modbus-only mapping); the mapping must outlive the table.
  SourceTable(const Database* db, const Mapping& mapping) : SourceTable(std::vector<InputDbc>{{"", db}}, mapping) {}
  // Several inputs (buses), each with its own DBC (or none); frames say which one they came from.
  SourceTable(std::vector<InputDbc> inputs, const Mapping& mapping) : inputs_(std::move(inputs)), mapping_(mapping) {}
  std::span<const InputDbc> inputs() const { return inputs_; }

  // The indices of output m's sources in the order it names them, adding those not seen before.
  // Throws MappingError when a DBC source does not resolve.
  std::vector<int> add(const OutputMapping& m);
  // Frames of the messages guard protects pass its checks before they are decoded (null: none).
  void set_e2e(E2eGuard* guard) { e2e_ = guard; }
  // Decodes the frame with the DBC of the input it came from (frame.input) into the sources it
  // carries (remote and error frames carry none).
  FrameUse on_frame(const CanFrame& frame);
  // A Modbus (or other named) value; false when no source has that key.
  bool on_value(std::string_view key, double value, bool valid, std::int64_t t_ns);

  const Source& operator[](int index) const { return sources_[static_cast<std::size_t>(index)]; }
  // The (id, extended) of every DBC message a source reads from that input, sorted.
  std::vector<std::pair<std::uint32_t, bool>> used_ids(int input = 0) const;

 private:
  struct MessageUse {
    int input = 0;
    std::vector<int> sources;  // per signal index, -1 = unused
  };
  std::vector<InputDbc> inputs_;
  const Mapping& mapping_;
  std::vector<Source> sources_;
  std::unordered_map<std::string, int> by_key_;
  std::unordered_map<const DbcMessage*, MessageUse> by_message_;
  std::vector<DecodedSignal> scratch_;
  E2eGuard* e2e_ = nullptr;
};

}  // namespace meter::controller
