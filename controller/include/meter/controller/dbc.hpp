// DBC database: parser, decoder (payload -> physical) and encoder (physical -> payload).
// Pure functions on plain data; no I/O except load_dbc().
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "meter/controller/can_frame.hpp"

namespace meter::controller {

// Thrown for a DBC that cannot be understood: "file:line: what was expected".
class DbcError : public std::runtime_error {
 public:
  DbcError(std::string file, int line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what), file_(std::move(file)), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

enum class ValueType : std::uint8_t { Integer, Float32, Float64 };

struct MuxRange {
  std::uint64_t lo, hi;
};

struct DbcSignal {
  std::string name;
  std::uint16_t start_bit = 0;   // DBC numbering: Intel = LSB, Motorola = MSB (sawtooth)
  std::uint16_t length = 1;
  bool little_endian = true;     // @1 Intel, @0 Motorola
  bool is_signed = false;
  ValueType value_type = ValueType::Integer;
  double factor = 1.0, offset = 0.0;
  double minimum = 0.0, maximum = 0.0;  // [0|0] (or min >= max) = no range given
  std::string unit;
  std::vector<std::string> receivers;
  std::string comment;
  std::vector<std::pair<std::int64_t, std::string>> choices;  // VAL_ table
  // Multiplexing: is_multiplexor for 'M' (and 'mNM'); multiplexed signals name their switch
  // (index into the message's signals) and the switch values that make them present.
  bool is_multiplexor = false;
  int mux_switch = -1;
  std::vector<MuxRange> mux_ranges;
  int line = 0;  // where it was defined

  bool has_range() const { return minimum < maximum; }
  // Byte count a payload must have for this signal to be fully present.
  std::size_t bytes_needed() const;
  const std::string* choice(std::int64_t raw) const;
};

struct DbcMessage {
  std::uint32_t id = 0;  // without the extended flag
  bool extended = false;
  std::string name;
  std::uint8_t size = 8;  // DLC in bytes (up to 64)
  std::string transmitter;
  std::vector<DbcSignal> signals;
  std::string comment;
  std::optional<int> cycle_time_ms;  // BA_ "GenMsgCycleTime" (message value or the default)
  bool j1939 = false;                 // matched by PGN and J1939 'not available' rules apply
  bool fd = false;                    // VFrameFormat says CAN FD
  int line = 0;

  int find_signal(std::string_view name) const;  // -1 if absent
};

// J1939 parameter group number of a 29-bit id (PDU1: destination byte cleared).
std::uint32_t j1939_pgn(std::uint32_t id29);

struct DbcWarning {
  int line;
  std::string text;
};

class Database {
 public:
  std::string file;  // for messages
  std::string version;
  std::vector<std::string> nodes;
  std::vector<DbcMessage> messages;
  std::vector<DbcWarning> warnings;  // tolerated problems (unknown references, duplicates...)
  std::string protocol_type;         // BA_ "ProtocolType" (e.g. "J1939")

  // Message for a received frame: exact id first, then (29-bit frames only) J1939 PGN match.
  const DbcMessage* find(std::uint32_t id, bool extended) const;
  const DbcMessage* find(std::string_view name) const;
  void build_index();  // called by the parser; call again after editing messages by hand

 private:
  std::unordered_map<std::uint64_t, std::size_t> by_id_;
  std::unordered_map<std::uint32_t, std::size_t> by_pgn_;
};

// Parses DBC text (UTF-8, or cp1252 which is converted to UTF-8). Throws DbcError.
Database parse_dbc(std::string_view text, const std::string& file = "<dbc>");
Database load_dbc(const std::string& path);  // throws DbcError (also for unreadable files)

enum class DecodeStatus : std::uint8_t {
  Valid,
  ShortFrame,    // the frame is shorter than the bytes this signal needs
  OutOfRange,    // outside the DBC [min|max]
  NotAvailable,  // J1939 'not available' raw pattern (all ones)
  ErrorValue,    // J1939 'error' raw pattern
  NotFinite,     // float signal carried NaN or Inf: never sent as a number
};
std::string_view to_string(DecodeStatus status);

struct DecodedSignal {
  int signal = -1;  // index into DbcMessage::signals
  std::uint64_t raw = 0;     // raw bits as unsigned (two's complement for signed)
  double physical = 0.0;     // 0 when status is NotFinite
  DecodeStatus status = DecodeStatus::Valid;
  std::int64_t raw_signed() const { return static_cast<std::int64_t>(raw); }
};

// Raw bits of one signal (sign-extended into the uint64 when signed). Payload shorter than needed:
// missing bytes read as zero (decode() reports ShortFrame for them).
std::uint64_t extract_raw(const DbcSignal& s, std::span<const std::uint8_t> payload);
void insert_raw(const DbcSignal& s, std::uint64_t raw, std::span<std::uint8_t> payload);
// Physical value of raw bits (float types reinterpret the bits).
double raw_to_physical(const DbcSignal& s, std::uint64_t raw);

// Decodes every present signal of the message (inactive multiplexed signals are skipped).
// Appends to out (cleared first); returns the number decoded.
std::size_t decode(const DbcMessage& m, std::span<const std::uint8_t> payload,
                   std::vector<DecodedSignal>& out);

// Encoder: physical values by signal name -> payload of m.size bytes. Signals not listed are 0 raw
// (multiplexed signals whose switch value does not select them are left out). Values are rounded
// to the nearest raw step; a value that does not fit the raw width throws std::out_of_range naming
// the signal. Unknown signal names throw std::invalid_argument.
std::vector<std::uint8_t> encode(const DbcMessage& m,
                                 std::span<const std::pair<std::string_view, double>> values);
// Raw for a physical value (rounded, range-checked against the bit width).
std::uint64_t physical_to_raw(const DbcSignal& s, double physical);

}  // namespace meter::controller
