// DBC database: messages, signals and their attributes as parsed from a DBC file, and the parser.
// Pure functions on plain data; no I/O except load_dbc(). Decoding and encoding: dbc/codec.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

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

}  // namespace meter::controller
