// Frames to recording lines (the grammar is in meter/protocol/recording.hpp and docs/protocol.md).
#include <charconv>
#include <cstdio>
#include <string>
#include <system_error>
#include <type_traits>
#include <variant>

#include "meter/protocol/recording.hpp"
#include "recording/recording_text.hpp"

namespace meter::protocol {

namespace {

// Shortest text that reads back to the same double (std::to_chars without a precision).
void append_double(std::string& out, double value) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, r.ptr);
}

void append_hex(std::string& out, std::uint64_t value, int digits) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "0x%0*llx", digits, static_cast<unsigned long long>(value));
  out += buffer;
}

void append_updates(std::string& out, const std::vector<SignalUpdate>& updates) {
  for (const auto& u : updates) {
    out += ' ';
    if (const auto* info = find_signal(u.id)) {
      out += info->name;
    } else {
      out += '#' + std::to_string(u.id);
    }
    out += '=';
    append_double(out, u.value);
    out += ':';
    out += to_string(u.status);
    if (u.has_text) {
      out += ':';
      detail::append_quoted(out, u.text);
    }
  }
}

struct FieldWriter {
  std::string& out;
  void operator()(const Hello& h) const {
    out += " role=" + std::string(to_string(h.role)) + " version=" + std::to_string(h.protocol_version) + " catalog=";
    append_hex(out, h.catalog_hash, 16);
    out += " signals=" + std::to_string(h.signal_count) + " heartbeat_ms=" + std::to_string(h.heartbeat_period_ms) +
           " name=";
    detail::append_quoted(out, h.name);
    out += " flags=";
    append_hex(out, h.flags, 2);
    out += " source=";
    detail::append_quoted(out, h.catalog_source);
    if (h.key_id != 0) {  // an authenticated link's HELLO: its key id and nonce
      out += " key=" + std::to_string(h.key_id) + " nonce=";
      for (std::uint8_t b : h.nonce) {
        char hex[4];
        std::snprintf(hex, sizeof hex, "%02x", b);
        out += hex;
      }
    }
  }
  void operator()(const Snapshot& s) const {
    out += s.complete ? " complete=1" : " complete=0";
    append_updates(out, s.signals);
  }
  void operator()(const Delta& d) const { append_updates(out, d.signals); }
  void operator()(const Heartbeat&) const {}
  void operator()(const Status& s) const {
    out += " frames=" + std::to_string(s.frames_rendered) + " last_seq=" + std::to_string(s.last_sequence_applied) +
           " faults=";
    append_hex(out, s.fault_flags, 8);
  }
  void operator()(const CatalogChunk& c) const {
    out += " hash=";
    append_hex(out, c.catalog_hash, 16);
    out += " piece=" + std::to_string(c.index) + " count=" + std::to_string(c.count) + " bytes=";
    detail::append_quoted(out, c.bytes);  // a piece may end inside a UTF-8 sequence: raw bytes
  }
  void operator()(const Close& c) const {
    out += " reason=" + detail::close_reason_token(c.reason) + " text=";
    detail::append_quoted(out, c.text);
  }
};

}  // namespace

std::string format_ns(std::int64_t ns) {
  // Magnitude as unsigned, so INT64_MIN has one too.
  const bool negative = ns < 0;
  const std::uint64_t magnitude = negative ? ~static_cast<std::uint64_t>(ns) + 1 : static_cast<std::uint64_t>(ns);
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%s%llu.%09llu", negative ? "-" : "",
                static_cast<unsigned long long>(magnitude / 1'000'000'000ULL),
                static_cast<unsigned long long>(magnitude % 1'000'000'000ULL));
  return buffer;
}

std::string recording_header(std::uint64_t catalog_hash) {
  std::string out = "# " + std::string(kRecordingFormat) + " catalog=";
  append_hex(out, catalog_hash, 16);
  return out;
}

std::string format_line(const RecordedFrame& recorded) {
  const Frame& f = recorded.frame;
  std::string out = "(" + format_ns(recorded.received_ns) + ") " + std::string(to_string(type_of(f.message))) +
                    " seq=" + std::to_string(f.sequence) + " sent=" + format_ns(f.timestamp_ns);
  std::visit(FieldWriter{out}, f.message);
  return out;
}

}  // namespace meter::protocol
