// The wire format as pure functions on byte spans: no sockets, no clocks, no global state, so every
// rule in docs/protocol.md is testable (and fuzzable) on plain bytes.
//
// Frame = 32-byte header + payload, all integers little-endian:
//   0  u32 magic "MTRL" (bytes 4D 54 52 4C)   4  u8 version (3)   5  u8 type   6  u16 flags
//   8  u32 payload length                    12  u64 sequence    20  i64 sender timestamp ns
//   28 u32 CRC-32C over bytes 0..27 and the payload
// and, when flag bit 0 (kFrameTagged) is set, a kTagSize-byte MAC tag after the payload
// (meter/protocol/frame_tag.hpp computes and checks it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol {

inline constexpr std::uint32_t kMagic = 0x4C52544DU;  // "MTRL" as bytes on the wire
// 2: HELLO flags + catalog source, CATALOG. 3: frame MAC tag (header flag bit 0), HELLO key id + nonce.
inline constexpr std::uint8_t kProtocolVersion = 3;
inline constexpr std::size_t kHeaderSize = 32;
inline constexpr std::size_t kMaxFrameSize = 65536;
inline constexpr std::size_t kMaxPayloadSize = kMaxFrameSize - kHeaderSize;
inline constexpr std::size_t kMaxTextBytes = 255;
// Header flag bit 0: a MAC tag of kTagSize bytes follows the payload (not counted in its length).
inline constexpr std::uint16_t kFrameTagged = 1;
inline constexpr std::size_t kTagSize = 16;    // 128-bit tag (docs/security.md says why)
inline constexpr std::size_t kNonceSize = 16;  // HELLO's per-connection freshness value
inline constexpr std::size_t kMaxNameBytes = 64;
// The largest signal entry: id, status, flags, value, text length, text.
inline constexpr std::size_t kMaxEntrySize = 2 + 1 + 1 + 8 + 1 + kMaxTextBytes;

// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78, init and final xor 0xFFFFFFFF).
// crc32c("123456789") == 0xE3069283. `crc` continues a previous result (0 to start).
std::uint32_t crc32c(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

enum class MessageType : std::uint8_t {
  Hello = 1,
  Snapshot = 2,
  Delta = 3,
  Heartbeat = 4,
  Status = 5,
  Close = 6,
  Catalog = 7,
};
std::string_view to_string(MessageType type);

enum class Role : std::uint8_t { Publisher = 1, Subscriber = 2 };
std::string_view to_string(Role role);

// HELLO flag bits.
inline constexpr std::uint8_t kHelloTakesCatalog = 1;  // subscriber: send me your catalog if ours differ

struct Hello {
  Role role = Role::Publisher;
  std::uint16_t protocol_version = kProtocolVersion;
  std::uint64_t catalog_hash = 0;
  std::uint16_t signal_count = 0;         // informational: entries in the sender's catalog
  std::uint32_t heartbeat_period_ms = 0;  // the receiver uses max(own, this) for loss detection
  std::string name;                       // at most kMaxNameBytes
  std::string catalog_source;             // the sender's catalog file, for refusals; at most kMaxTextBytes
  std::uint8_t flags = 0;                 // kHelloTakesCatalog; other bits reserved (0)
  std::uint32_t key_id = 0;               // the link key this end tags with; 0 = unauthenticated
  std::array<std::uint8_t, kNonceSize> nonce{};  // fresh random bytes per connection (0 without a key)
  bool operator==(const Hello&) const = default;
};

// One piece of the publisher's catalog (its VSS JSON text), sent after HELLO to a subscriber that
// takes it. Pieces arrive in order, index 0..count-1; their bytes concatenated are the file.
struct CatalogChunk {
  std::uint64_t catalog_hash = 0;  // the hash the assembled catalog must have (as in HELLO)
  std::uint16_t index = 0;
  std::uint16_t count = 1;
  std::string bytes;               // at most kMaxCatalogChunkBytes
  bool operator==(const CatalogChunk&) const = default;
};
inline constexpr std::size_t kCatalogChunkOverhead = 16;  // hash u64, index u16, count u16, length u32
inline constexpr std::size_t kMaxCatalogChunkBytes = kMaxPayloadSize - kCatalogChunkOverhead;

// One signal's value in a SNAPSHOT or DELTA.
struct SignalUpdate {
  SignalId id = 0;
  SignalStatus status = SignalStatus::NotAvailable;
  double value = 0.0;  // always finite on the wire
  bool has_text = false;
  std::string text;    // at most kMaxTextBytes
  bool operator==(const SignalUpdate&) const = default;
};

struct Snapshot {
  bool complete = true;  // false: more SNAPSHOT frames of this catch-up follow
  std::vector<SignalUpdate> signals;
  bool operator==(const Snapshot&) const = default;
};

struct Delta {
  std::vector<SignalUpdate> signals;
  bool operator==(const Delta&) const = default;
};

struct Heartbeat {
  bool operator==(const Heartbeat&) const = default;
};

// Health, in both directions. From the view: frames rendered, the sequence of the last SNAPSHOT/
// DELTA applied, kViewFault* flags. From the controller: frames received, frames lost (kernel
// drops), kControllerFault* flags.
struct Status {
  std::uint64_t frames_rendered = 0;        // the controller's: frames received
  std::uint64_t last_sequence_applied = 0;  // the controller's: frames lost
  std::uint32_t fault_flags = 0;
  bool operator==(const Status&) const = default;
};

// STATUS fault flags. A bit stays set for kViewFaultHoldMs after the fault last happened, so a
// STATUS lost to latest-wins coalescing cannot hide it, and clears after. Bits 0-15 are the view's,
// 16-31 the controller's; receivers accept bits they do not know (they name them "bit N"), so a
// newer peer can report faults an older one has no name for.
// From the view, bits 0-15:
inline constexpr std::uint32_t kViewFaultFrameDeadline = 1U << 0;  // a frame ended after the next one was due
inline constexpr std::uint32_t kViewFaultDumpFailed = 1U << 1;     // a requested PNG dump could not be written
inline constexpr std::uint32_t kViewFaultIntegrity = 1U << 2;      // the integrity monitor found a wrong or frozen safety region
inline constexpr std::uint32_t kViewFaultDisplayFrozen = 1U << 3;  // the display took no frame within its wait (no frame callback or page flip)
inline constexpr int kViewFaultHoldMs = 1000;
// From the controller, bits 16-31:
inline constexpr std::uint32_t kControllerFaultBusWarning = 1U << 16;  // error-warning (error counter >= 96)
inline constexpr std::uint32_t kControllerFaultBusPassive = 1U << 17;  // error-passive (>= 128)
inline constexpr std::uint32_t kControllerFaultBusOff = 1U << 18;      // bus-off: the CAN controller left the bus
inline constexpr std::uint32_t kControllerFaultFramesLost = 1U << 19;  // the kernel dropped frames (held 1 s)
inline constexpr std::uint32_t kControllerFaultReplaySlip = 1U << 20;  // a replay fell behind its log (held 1 s)
// "frame-deadline", "dump-failed", "integrity", "bus-warning", "bus-passive", "bus-off",
// "frames-lost", "replay-slip", "bit N", joined with ", "; "none" for 0.
std::string describe_fault_flags(std::uint32_t flags);

enum class CloseReason : std::uint8_t {
  Normal = 0,
  VersionMismatch = 1,
  CatalogMismatch = 2,
  RoleMismatch = 3,
  NotAllowed = 4,
  ProtocolError = 5,
  Timeout = 6,
  Authentication = 7,  // no key, unknown key id, or a HELLO whose tag does not verify
};
std::string_view to_string(CloseReason reason);

struct Close {
  CloseReason reason = CloseReason::Normal;
  std::string text;  // at most kMaxTextBytes, human-readable
  bool operator==(const Close&) const = default;
};

using Message = std::variant<Hello, Snapshot, Delta, Heartbeat, Status, Close, CatalogChunk>;
MessageType type_of(const Message& message);

struct FrameHeader {
  std::uint8_t version = kProtocolVersion;
  std::uint8_t type = 0;  // raw, so an unknown type can still be reported
  std::uint16_t flags = 0;
  std::uint32_t payload_length = 0;
  std::uint64_t sequence = 0;
  std::int64_t timestamp_ns = 0;
  std::uint32_t crc = 0;
  bool tagged() const { return (flags & kFrameTagged) != 0; }
};

struct Frame {
  std::uint64_t sequence = 0;
  std::int64_t timestamp_ns = 0;
  Message message;
};

// Appends one encoded frame to `out`. Throws std::length_error if the payload would exceed
// kMaxPayloadSize, std::invalid_argument for a value the format cannot carry (non-finite value,
// text/name too long, unknown status) — the encoder never produces a frame the decoder rejects.
// With `key`, the frame is tagged: flag bit 0 set and the MAC tag (frame_tag.hpp) appended.
struct FrameKey;
void encode(const Frame& frame, std::vector<std::uint8_t>& out, const FrameKey* key = nullptr);
std::vector<std::uint8_t> encode(const Frame& frame, const FrameKey* key = nullptr);

// Encoded size of one entry / of a DELTA or SNAPSHOT holding `entries` bytes of entries: lets the
// sender split a large update across frames without encoding twice.
std::size_t encoded_size(const SignalUpdate& update);
inline constexpr std::size_t kUpdateListOverhead = 4;  // flags u8, reserved u8, count u16

enum class DecodeError : std::uint8_t {
  None = 0,
  Truncated,         // fewer bytes than the header or than header + payload length
  BadMagic,
  BadVersion,
  Oversized,         // payload length > kMaxPayloadSize
  BadCrc,
  UnknownType,
  Malformed,         // CRC fine, payload breaks the format
  // Set by the link's tag check, never by decode(): the frame decoded, but on an authenticated
  // link its MAC tag is wrong (forged, altered, or keyed for another connection or direction) or
  // missing (a MAC stripped, or a peer that does not authenticate).
  BadMac,
  MissingMac,
};
std::string_view to_string(DecodeError error);

struct DecodeResult {
  DecodeError error = DecodeError::None;
  std::size_t frame_size = 0;  // bytes of the frame (header + payload + tag) when the header was readable
  // The frame's bytes (frame_size of them) when it decoded: a view of the input, valid as long as
  // the bytes given to decode() (or until the StreamAssembler's next append()/next()).
  std::span<const std::uint8_t> bytes;
  FrameHeader header;          // valid when error is not Truncated-before-header / BadMagic
  Frame frame;                 // valid when error == None
  std::string detail;          // what was wrong, for logs ("entry 3: unknown signal id 999")
};

// Header checks only (magic, version, size limit): what a stream reader needs to know how many
// bytes to wait for. Truncated here means "fewer than kHeaderSize bytes".
DecodeResult peek_header(std::span<const std::uint8_t> bytes);

// Decodes the frame at the start of `bytes`. Bytes after the frame are ignored (frame_size tells
// how many were used); a datagram transport treats leftovers as an error itself.
DecodeResult decode(std::span<const std::uint8_t> bytes);

// Reassembles frames from a byte stream (TCP) that arrives in arbitrary pieces. Pure: feed bytes,
// take frames. Once the framing is lost (bad magic, unsupported version, oversized length, CRC
// mismatch: the length field can no longer be trusted) the assembler reports that error once and
// then stays broken; the caller closes the connection. A frame with a good CRC but an unknown type
// or a malformed payload is reported and skipped, and the stream continues.
class StreamAssembler {
 public:
  void append(std::span<const std::uint8_t> bytes);
  // The next complete frame or error; std::nullopt when more bytes are needed (or broken).
  std::optional<DecodeResult> next();
  bool broken() const { return broken_; }
  std::size_t buffered() const { return buffer_.size() - start_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::size_t start_ = 0;  // consumed prefix, compacted lazily to keep append amortised O(1)
  bool broken_ = false;
};

// True if `text` is well-formed UTF-8 (the decoder rejects text fields that are not).
bool is_valid_utf8(std::string_view text);

}  // namespace meter::protocol
