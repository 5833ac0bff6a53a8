// The controller-to-view link: endpoints, the Publisher (controller side) and the Subscriber
// (view side). Both are single-threaded and poll-driven: nothing happens behind the caller's back,
// so the controller and the view can fold the link into their own event loops via wait_fd().
//
// State model (the attribute-processor idea): the Publisher keeps the full current state of every
// catalog signal plus, per connected view, one dirty flag per signal. set() only records the value
// and raises the dirty flags; poll() sends each view one coalesced DELTA with exactly the signals
// that changed since that view last got them. A view that (re)connects first gets a SNAPSHOT of the
// whole state. A view that stops reading never makes the Publisher queue without bound: at most one
// batch of frames is ever pending per view, later changes just stay dirty and overwrite each other.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/endpoint.hpp"
#include "meter/protocol/link_options.hpp"
#include "meter/protocol/signal_table.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::protocol {

// Frames dropped or connections closed because of bad input, by class.
struct BadFrameCounts {
  std::uint64_t bad_magic = 0;
  std::uint64_t crc = 0;
  std::uint64_t version = 0;
  std::uint64_t truncated = 0;
  std::uint64_t oversized = 0;
  std::uint64_t unknown_type = 0;
  std::uint64_t malformed = 0;  // good CRC, but the payload breaks the format (bad id, NaN, ...)
  std::uint64_t mac = 0;        // authenticated link: the MAC tag does not verify
  std::uint64_t no_mac = 0;     // authenticated link: a frame without a MAC tag (stripped, downgraded)
  std::uint64_t total() const {
    return bad_magic + crc + version + truncated + oversized + unknown_type + malformed + mac + no_mac;
  }
};

struct LinkStats {
  std::uint64_t messages_sent = 0, messages_received = 0;
  std::uint64_t bytes_sent = 0, bytes_received = 0;
  std::uint64_t hellos_sent = 0, hellos_received = 0;
  std::uint64_t snapshots_sent = 0, snapshots_received = 0;
  std::uint64_t deltas_sent = 0, deltas_received = 0;
  std::uint64_t heartbeats_sent = 0, heartbeats_received = 0;
  std::uint64_t status_sent = 0, status_received = 0;
  std::uint64_t catalog_pieces_sent = 0, catalog_pieces_received = 0;  // CATALOG frames
  std::uint64_t catalogs_taken = 0;           // Subscriber: publisher catalogs assembled and used
  std::uint64_t signal_updates_sent = 0;      // entries inside SNAPSHOT/DELTA frames
  std::uint64_t signal_updates_applied = 0;   // entries that changed the local state
  std::uint64_t coalesced_updates = 0;        // set() calls that overwrote a value not yet sent
  std::uint64_t sequence_gaps = 0;            // times a received sequence number skipped ahead
  std::uint64_t sequence_frames_missed = 0;   // sum of the skipped numbers
  std::uint64_t sequence_replays = 0;         // authenticated link: frames with a used sequence, dropped
  BadFrameCounts bad_frames;
  std::uint64_t write_stalls = 0;             // sends that hit a full socket buffer
  std::uint64_t max_pending_bytes = 0;        // high-water mark of bytes queued for one peer
  std::uint64_t connects = 0;                 // links established (handshake done)
  std::uint64_t reconnects = 0;               // Subscriber: links established after a loss
  std::uint64_t link_losses = 0;              // heartbeat silence or peer closed
  std::uint64_t handshakes_refused = 0;       // version / catalog / role / key mismatch, either side
  std::uint64_t peers_rejected = 0;           // SO_PEERCRED uid not in the allow-list
  bool link_up = false;                       // Publisher: at least one peer in sync
};

// Log lines from the link (bad input, link loss, refusals) go through this sink, rate-limited per
// kind of event so a peer flooding garbage cannot flood the log. Default: stderr.
using LogSink = std::function<void(std::string_view line)>;
void set_log_sink(LogSink sink);  // empty = back to stderr; resets the rate-limit budgets

// Controller side: listens on the endpoint, serves any number of views. Latest-value semantics:
// set() only records the value and marks it dirty per peer; poll() sends coalesced DELTAs.
class Publisher {
 public:
  // Binds and listens. Unix: refuses (std::runtime_error) if a live publisher already owns the path,
  // removes a stale socket file, creates the socket with mode 0600. TCP: binds the given host (use
  // 127.0.0.1/localhost to stay on loopback). Throws std::runtime_error with a clear message.
  explicit Publisher(const Endpoint& where, LinkOptions options = {});
  ~Publisher();
  Publisher(Publisher&&) noexcept;
  Publisher& operator=(Publisher&&) noexcept;
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  // Unknown id: std::invalid_argument. A non-finite value is never sent: it is recorded as
  // value 0 with status Invalid (and logged), so no NaN reaches the view.
  void set(SignalId id, double value, SignalStatus status);
  // Text longer than kMaxTextBytes is cut at a UTF-8 boundary.
  void set_text(SignalId id, std::string_view text, SignalStatus status);
  const SignalState& get(SignalId id) const;  // unknown id: std::out_of_range

  // Accepts views, reads HELLO/STATUS/HEARTBEAT, flushes deltas and heartbeats, detects loss.
  // Returns once timeout has elapsed (0 = one non-blocking round); never blocks longer.
  void poll(std::chrono::milliseconds timeout);
  // An epoll fd that becomes readable when poll() has work (socket activity or a heartbeat due).
  int wait_fd() const;
  std::size_t peer_count() const;  // views with a completed handshake
  LinkStats stats() const;
  Endpoint endpoint() const;       // the bound endpoint (TCP port 0 resolved)
  std::string last_error() const;  // the most recent refusal / loss reason, "" if none

  struct PeerStatus {
    std::uint64_t frames_rendered;
    std::uint64_t last_sequence_applied;
    std::uint32_t fault_flags;
  };
  std::vector<PeerStatus> peer_status() const;  // one per handshaken view, last STATUS received
  // The controller's own health for every view: frames received, frames lost, kControllerFault*
  // flags. Sent to each view at once when the flags changed (and to a view that connects, after
  // its SNAPSHOT); new counts alone go in place of the next heartbeat, so a count that changes
  // every tick costs no extra frames.
  void send_status(std::uint64_t frames_received, std::uint64_t frames_lost, std::uint32_t fault_flags);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// View side: connects (and reconnects with backoff), gets SNAPSHOT then DELTAs.
class Subscriber {
 public:
  // Never throws for an unreachable publisher (it keeps retrying); throws std::runtime_error only
  // for local failures (socket creation).
  explicit Subscriber(const Endpoint& where, LinkOptions options = {});
  ~Subscriber();
  Subscriber(Subscriber&&) noexcept;
  Subscriber& operator=(Subscriber&&) noexcept;
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;

  // Connects/reconnects, reads, applies, sends heartbeats. Returns true as soon as any signal
  // changed (or after timeout with false); never blocks longer than timeout.
  bool poll(std::chrono::milliseconds timeout);
  bool link_up() const;  // false before the first SNAPSHOT and after heartbeat loss
  // Everything received so far, one entry per catalog signal (NotAvailable until the SNAPSHOT).
  // The view's bindings read it in place, find() per signal; changed_at() tells which signals changed
  // since a version a consumer saw.
  const SignalTable& signals() const;
  const SignalState& get(SignalId id) const;  // signals().get(id); unknown id: std::out_of_range
  // The catalog signals() follows: the active catalog at construction, or the publisher's once
  // taken (LinkOptions::take_peer_catalog). catalog_changes() counts how often it was replaced, so
  // a consumer that resolved names to ids knows to resolve them again.
  const Catalog& catalog() const;
  std::uint64_t catalog_changes() const;
  std::uint64_t state_version() const;        // signals().version(): increments on every applied change
  std::int64_t last_sender_time_ns() const;   // sender timestamp (CLOCK_MONOTONIC) of last applied msg
  std::uint64_t last_sequence_applied() const;
  // Queues a STATUS for the controller (latest wins if the socket is full); sent immediately when
  // the link is up, else at the next handshake.
  void send_status(std::uint64_t frames_rendered, std::uint32_t fault_flags);
  // The publisher's last STATUS (frames_rendered = frames it received, last_sequence_applied =
  // frames it lost, kControllerFault* flags); none before the first.
  std::optional<Status> publisher_status() const;
  LinkStats stats() const;
  int wait_fd() const;  // epoll fd readable when poll() has work
  std::string last_error() const;

  // Called with every frame received from the publisher (HELLO, SNAPSHOT, DELTA, HEARTBEAT, CLOSE),
  // before it is handled, from inside poll(). For tools that show the link's traffic (meter-linkdump).
  using FrameObserver = std::function<void(const Frame& frame)>;
  void set_frame_observer(FrameObserver observer);  // empty = none

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meter::protocol
