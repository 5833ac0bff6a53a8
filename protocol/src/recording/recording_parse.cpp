// Recording lines back to frames. Everything a line may hold is checked against the limits the wire
// format has (catalog ids, finite values, text and name lengths, UTF-8, payload size), so a parsed
// frame is always one the encoder accepts and the decoder would have delivered.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <system_error>

#include "meter/protocol/recording.hpp"
#include "recording/recording_text.hpp"

namespace meter::protocol {

RecordingError::RecordingError(std::string file, std::size_t line, const std::string& message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + message), file_(std::move(file)), line_(line) {}

namespace {

class LineParser {
 public:
  LineParser(std::string_view text, std::string_view file, std::size_t line) : file_(file), line_(line) {
    auto tokens = detail::split_tokens(text);
    if (!tokens) fail("a quoted text is not closed (missing '\"')");
    tokens_ = std::move(*tokens);
  }

  [[noreturn]] void fail(const std::string& what) const { throw RecordingError(std::string(file_), line_, what); }

  bool done() const { return next_ == tokens_.size(); }
  std::string_view take(std::string_view what) {
    if (done()) fail("line ends where " + std::string(what) + " was expected");
    return tokens_[next_++];
  }
  // The value of the next token, which must be "key=value".
  std::string_view field(std::string_view key) {
    const auto token = take(std::string(key) + "=");
    if (token.size() <= key.size() || token.substr(0, key.size()) != key || token[key.size()] != '=') {
      fail("expected " + std::string(key) + "=..., got '" + std::string(token) + "'");
    }
    return token.substr(key.size() + 1);
  }

  template <typename T>
  T number(std::string_view key, std::string_view text, int base = 10) const {
    T value{};
    const auto* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, value, base);
    if (text.empty() || r.ec == std::errc::result_out_of_range || r.ptr != end || r.ec != std::errc()) {
      fail(std::string(key) + ": expected an integer 0.." + std::to_string(std::numeric_limits<T>::max()) +
           (base == 16 ? " in hex" : "") + ", got '" + std::string(text) + "'");
    }
    return value;
  }
  template <typename T>
  T integer(std::string_view key) {
    return number<T>(key, field(key));
  }
  template <typename T>
  T hex(std::string_view key) {
    const auto text = field(key);
    if (text.size() < 3 || text.substr(0, 2) != "0x") fail(std::string(key) + ": expected 0x<hex digits>, got '" + std::string(text) + "'");
    return number<T>(key, text.substr(2), 16);
  }

  std::int64_t ns(std::string_view what, std::string_view text) const {
    const auto bad = [&] {
      fail(std::string(what) + ": expected seconds with 9 decimals (12.000000042), got '" + std::string(text) + "'");
    };
    const bool negative = !text.empty() && text.front() == '-';
    const auto body = negative ? text.substr(1) : text;
    const auto dot = body.find('.');
    if (dot == std::string_view::npos || dot == 0 || body.size() - dot - 1 != 9) bad();
    for (std::size_t i = 0; i < body.size(); ++i)
      if (i != dot && (body[i] < '0' || body[i] > '9')) bad();
    std::uint64_t seconds = 0, fraction = 0;
    if (std::from_chars(body.data(), body.data() + dot, seconds).ec != std::errc()) bad();
    std::from_chars(body.data() + dot + 1, body.data() + body.size(), fraction);
    const std::uint64_t limit = negative ? (1ULL << 63) : (1ULL << 63) - 1;
    if (seconds > limit / 1'000'000'000ULL || seconds * 1'000'000'000ULL > limit - fraction) {
      fail(std::string(what) + ": '" + std::string(text) + "' is outside the 64-bit nanosecond range");
    }
    const std::uint64_t magnitude = seconds * 1'000'000'000ULL + fraction;
    return negative ? static_cast<std::int64_t>(~magnitude + 1) : static_cast<std::int64_t>(magnitude);
  }

  // A quoted text's bytes, at most max_bytes (any bytes: a catalog piece may end inside a UTF-8
  // sequence).
  std::string bytes(std::string_view what, std::string_view token, std::size_t max_bytes) const {
    std::string why;
    auto t = detail::unquote(token, why);
    if (!t) fail(std::string(what) + ": " + why);
    if (t->size() > max_bytes) {
      fail(std::string(what) + ": " + std::to_string(t->size()) + " bytes, the link carries at most " +
           std::to_string(max_bytes));
    }
    return *t;
  }
  // A quoted text, which the wire requires to be UTF-8.
  std::string text(std::string_view what, std::string_view token, std::size_t max_bytes) const {
    std::string t = bytes(what, token, max_bytes);
    if (!is_valid_utf8(t)) fail(std::string(what) + ": not valid UTF-8");
    return t;
  }

  SignalUpdate update(std::string_view token) const {
    SignalUpdate u;
    const auto eq = token.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      fail("expected a signal update NAME=VALUE:STATUS[:\"TEXT\"], got '" + std::string(token) + "'");
    }
    const auto name = token.substr(0, eq);
    const SignalInfo* info = nullptr;
    if (name.front() == '#') {
      info = find_signal(number<SignalId>("signal id", name.substr(1)));
    } else {
      info = find_signal(name);
    }
    if (info == nullptr) fail("unknown signal '" + std::string(name) + "' (not in this build's catalog)");
    u.id = info->id;
    const auto rest = token.substr(eq + 1);
    const auto colon = rest.find(':');
    if (colon == std::string_view::npos) {
      fail(std::string(name) + ": expected VALUE:STATUS after '=', got '" + std::string(rest) + "'");
    }
    const auto value_text = rest.substr(0, colon);
    const auto* end = value_text.data() + value_text.size();
    const auto r = std::from_chars(value_text.data(), end, u.value);
    if (value_text.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(u.value)) {
      fail(std::string(name) + ": expected a finite number, got '" + std::string(value_text) + "'");
    }
    const auto after = rest.substr(colon + 1);
    const auto text_colon = after.find(':');
    const auto status_text = after.substr(0, text_colon);
    const auto status = status_from_string(status_text);
    if (!status) {
      fail(std::string(name) + ": unknown status '" + std::string(status_text) +
           "' (valid, timed-out, invalid, not-available)");
    }
    u.status = *status;
    if (text_colon != std::string_view::npos) {
      u.has_text = true;
      u.text = text(std::string(name) + " text", after.substr(text_colon + 1), kMaxTextBytes);
    }
    return u;
  }

  std::vector<SignalUpdate> updates() {
    std::vector<SignalUpdate> out;
    std::size_t payload = kUpdateListOverhead;
    while (!done()) {
      out.push_back(update(take("a signal update")));
      payload += encoded_size(out.back());
    }
    if (payload > kMaxPayloadSize) {
      fail(std::to_string(out.size()) + " updates need " + std::to_string(payload) + " payload bytes, a frame holds " +
           std::to_string(kMaxPayloadSize));
    }
    return out;
  }

  void end() const {
    if (!done()) fail("unexpected '" + std::string(tokens_[next_]) + "' after the last field");
  }

 private:
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
  std::string_view file_;
  std::size_t line_;
};

Message parse_message(LineParser& p, std::string_view kind) {
  if (kind == "HELLO") {
    Hello h;
    const auto role = p.field("role");
    if (role == to_string(Role::Publisher)) {
      h.role = Role::Publisher;
    } else if (role == to_string(Role::Subscriber)) {
      h.role = Role::Subscriber;
    } else {
      p.fail("role: expected publisher or subscriber, got '" + std::string(role) + "'");
    }
    h.protocol_version = p.integer<std::uint16_t>("version");
    h.catalog_hash = p.hex<std::uint64_t>("catalog");
    h.signal_count = p.integer<std::uint16_t>("signals");
    h.heartbeat_period_ms = p.integer<std::uint32_t>("heartbeat_ms");
    h.name = p.text("name", p.field("name"), kMaxNameBytes);
    h.flags = p.hex<std::uint8_t>("flags");
    if ((h.flags & ~kHelloTakesCatalog) != 0) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", h.flags);
      p.fail("flags: " + std::string(hex) + " uses reserved bits (only 0x01, takes the catalog, is defined)");
    }
    h.catalog_source = p.text("source", p.field("source"), kMaxTextBytes);
    if (!p.done()) {  // an authenticated link's HELLO
      h.key_id = p.integer<std::uint32_t>("key");
      const auto nonce = p.field("nonce");
      if (nonce.size() != 2 * kNonceSize) p.fail("nonce: expected " + std::to_string(2 * kNonceSize) + " hex digits");
      for (std::size_t i = 0; i < kNonceSize; ++i) {
        h.nonce[i] = p.number<std::uint8_t>("nonce", nonce.substr(2 * i, 2), 16);
      }
    }
    p.end();
    return h;
  }
  if (kind == "SNAPSHOT") {
    Snapshot s;
    const auto complete = p.field("complete");
    if (complete != "0" && complete != "1") p.fail("complete: expected 0 or 1, got '" + std::string(complete) + "'");
    s.complete = complete == "1";
    s.signals = p.updates();
    return s;
  }
  if (kind == "DELTA") return Delta{p.updates()};
  if (kind == "HEARTBEAT") {
    p.end();
    return Heartbeat{};
  }
  if (kind == "STATUS") {
    Status s;
    s.frames_rendered = p.integer<std::uint64_t>("frames");
    s.last_sequence_applied = p.integer<std::uint64_t>("last_seq");
    s.fault_flags = p.hex<std::uint32_t>("faults");
    p.end();
    return s;
  }
  if (kind == "CATALOG") {
    CatalogChunk c;
    c.catalog_hash = p.hex<std::uint64_t>("hash");
    c.index = p.integer<std::uint16_t>("piece");
    c.count = p.integer<std::uint16_t>("count");
    if (c.count == 0) p.fail("count: expected at least 1 piece, got 0");
    if (c.index >= c.count) p.fail("piece: expected 0.." + std::to_string(c.count - 1) + " (count=" + std::to_string(c.count) + ")");
    c.bytes = p.bytes("bytes", p.field("bytes"), kMaxCatalogChunkBytes);
    p.end();
    return c;
  }
  if (kind == "CLOSE") {
    Close c;
    const auto reason = p.field("reason");
    const auto r = detail::close_reason_from_token(reason);
    if (!r) p.fail("reason: unknown close reason '" + std::string(reason) + "' (e.g. normal, protocol-error)");
    c.reason = *r;
    c.text = p.text("text", p.field("text"), kMaxTextBytes);
    p.end();
    return c;
  }
  p.fail("unknown message kind '" + std::string(kind) + "' (HELLO, SNAPSHOT, DELTA, HEARTBEAT, STATUS, CATALOG, CLOSE)");
}

}  // namespace

RecordedFrame parse_line(std::string_view text, std::string_view file, std::size_t line) {
  if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
  LineParser p(text, file, line);
  RecordedFrame out;
  const auto stamp = p.take("the receive time (S.NNNNNNNNN)");
  if (stamp.size() < 3 || stamp.front() != '(' || stamp.back() != ')') {
    p.fail("expected the receive time in parentheses, e.g. (12.000000042), got '" + std::string(stamp) + "'");
  }
  out.received_ns = p.ns("receive time", stamp.substr(1, stamp.size() - 2));
  const auto kind = p.take("the message kind");
  out.frame.sequence = p.integer<std::uint64_t>("seq");
  out.frame.timestamp_ns = p.ns("sent", p.field("sent"));
  out.frame.message = parse_message(p, kind);
  return out;
}

std::vector<RecordedFrame> parse_recording(std::istream& in, std::string_view file) {
  std::vector<RecordedFrame> out;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    out.push_back(parse_line(text, file, line));
  }
  if (in.bad()) throw RecordingError(std::string(file), 0, "read error");
  return out;
}

}  // namespace meter::protocol
