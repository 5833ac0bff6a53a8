// DBC database: messages, signals and their attributes as parsed from a DBC file, and their
// look-ups. Pure functions on plain data. The parser's entry points (parse_dbc, load_dbc): dbc/parse.hpp,
// included here; decoding and encoding: dbc/codec.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "meter/controller/dbc/parse.hpp"

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

// What a tolerated problem was: the lint report counts warnings by kind, --strict refuses them all.
enum class DbcWarningKind : std::uint8_t {
  MissingSemicolon,   // a statement without its ';': assumed to end with its line
  UnnamedComment,     // CM_ SG_ <id> "text" (no signal) or CM_ <id> "text" (no object keyword)
  UnknownReference,   // a comment, value table, attribute or value type for an undefined object
  StandardIdAbove7FF, // BO_ id above 0x7FF without the extended flag: taken as extended
  Duplicate,          // a message id, signal, value table or attribute defined twice
  UnknownAttributeType,
  SignalOutsideMessage,  // a signal reaching past the message size (never decoded as valid)
  SkippedStatement,   // a statement that could not be understood, skipped (the rest of the file is read)
  ReservedIdBits,     // BO_ id with bit 29 or 30 set (no part of a CAN id): ignored
  NotUtf8,            // the text is not UTF-8: read as Windows-1252 (what Vector tools write)
};
inline constexpr int kDbcWarningKinds = 10;
const char* to_string(DbcWarningKind k);  // "missing-semicolon", "unnamed-comment", ...

struct DbcWarning {
  DbcWarningKind kind;
  int line;
  std::string text;
};

// A BO_ or SG_ definition the parser skipped (it could not be understood): a mapping that uses it
// gets an error naming the definition and why, not "no such signal".
struct SkippedDefinition {
  std::string message;  // the message name (or id when the name could not be read)
  std::string signal;   // empty for a skipped BO_ (its SG_ lines are skipped with it)
  int line;
  std::string reason;
};

class Database {
 public:
  std::string file;  // for messages
  std::string version;
  std::vector<std::string> nodes;
  std::vector<DbcMessage> messages;
  std::vector<DbcWarning> warnings;  // tolerated problems (unknown references, duplicates...)
  std::vector<SkippedDefinition> skipped;
  std::string protocol_type;         // BA_ "ProtocolType" (e.g. "J1939")

  // Message for a received frame: exact id first, then (29-bit frames only) J1939 PGN match.
  const DbcMessage* find(std::uint32_t id, bool extended) const;
  const DbcMessage* find(std::string_view name) const;
  void build_index();  // called by the parser; call again after editing messages by hand
  // "; its definition at FILE:LINE was skipped: REASON" when message (and signal, if given) was
  // skipped by the parser, else empty: appended to "no such message/signal" errors.
  std::string skipped_note(std::string_view message, std::string_view signal = {}) const;

 private:
  std::unordered_map<std::uint64_t, std::size_t> by_id_;
  std::unordered_map<std::uint32_t, std::size_t> by_pgn_;
};

}  // namespace meter::controller
