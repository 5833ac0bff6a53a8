#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <optional>
#include <stdexcept>

#include "transport/channel.hpp"
#include "transport/clock.hpp"
#include "link/handshake.hpp"
#include "link/key_ring.hpp"
#include "link/session_auth.hpp"
#include "transport/log.hpp"
#include "transport/poller.hpp"
#include "transport/unique_fd.hpp"
#include "transport/unix_address.hpp"

namespace meter::protocol {

using detail::Channel;
using detail::Clock;
using detail::UniqueFd;

struct Subscriber::Impl {
  enum class Phase { Idle, Connecting, Handshake, Live };

  Endpoint where;
  LinkOptions options;
  std::uint64_t our_hash;
  std::unique_ptr<detail::KeyRing> keys;  // none: frames carry no MAC
  detail::Poller poller;
  std::unique_ptr<Channel> channel;
  Phase phase = Phase::Idle;
  bool got_hello = false;
  bool ever_live = false;
  Clock::time_point retry_at;
  std::chrono::milliseconds backoff;
  std::chrono::milliseconds peer_heartbeat{0};
  SignalTable table;
  std::uint64_t catalog_changes = 0;
  // Set between the publisher's HELLO and the last CATALOG piece when we take its catalog.
  std::optional<detail::CatalogAssembler> incoming_catalog;
  std::int64_t sender_time_ns = 0;
  std::uint64_t last_applied_seq = 0;
  std::optional<Status> pending_status;
  std::optional<Status> publisher_status;  // the publisher's last STATUS
  LinkStats stats;
  std::string last_error;
  bool changed = false;  // set by apply(), consumed by poll()
  FrameObserver observer;
  // A disconnect decided while Channel::receive() is still on the stack runs after it returns.
  struct PendingDisconnect {
    std::string why;
    bool loss;
  };
  std::optional<PendingDisconnect> pending_disconnect;

  Impl(const Endpoint& w, LinkOptions o)
      : where(w), options(std::move(o)),
        our_hash(options.catalog_hash_override.value_or(catalog_hash())),
        keys(checked_keys(where, options)),
        poller(std::max(options.heartbeat_period / 4, std::chrono::milliseconds(1))),
        retry_at(Clock::now()), backoff(options.reconnect_min) {
    if (options.heartbeat_period.count() <= 0) throw std::invalid_argument("heartbeat_period must be > 0 ms");
    if (options.missed_heartbeats_for_loss < 1) throw std::invalid_argument("missed_heartbeats_for_loss must be >= 1");
    if (options.reconnect_min.count() <= 0 || options.reconnect_max < options.reconnect_min) {
      throw std::invalid_argument("reconnect backoff needs 0 < reconnect_min <= reconnect_max");
    }
    if (options.name.empty()) options.name = "subscriber";
    if (options.allowed_uids.empty()) options.allowed_uids.push_back(::getuid());
    try_connect();
  }

  static std::unique_ptr<detail::KeyRing> checked_keys(const Endpoint& where, const LinkOptions& o) {
    if (auto why = link_security_error(where, o); !why.empty()) throw std::invalid_argument(why);
    if (o.key_file.empty()) return nullptr;
    return std::make_unique<detail::KeyRing>(o.key_file);
  }

  // Takes a changed key file; a connection whose key was removed is closed and made again with a
  // key still held. Checked once a second and before each connection attempt.
  void refresh_keys(bool now_please) {
    if (!keys || !keys->poll(options.name, now_please)) return;
    if (channel && channel->guard() != nullptr && !channel->guard()->keys_held()) {
      ++stats.handshakes_refused;
      channel->send(Close{CloseReason::Authentication, "key removed from the key file"}, stats);
      std::string ignored;
      channel->flush(stats, ignored);
      disconnect("a key this connection uses was removed from " + keys->path(), phase == Phase::Live);
    }
  }

  void note(const std::string& key, const std::string& text) {
    last_error = text;
    detail::log_limited(key, options.name + ": " + text);
  }

  // Closes the connection and schedules the next attempt with exponential backoff.
  void disconnect(const std::string& why, bool count_loss) {
    if (channel) {
      poller.remove(channel->fd());
      channel.reset();
    }
    if (count_loss) {
      ++stats.link_losses;
      note("link-lost", "link to " + where.to_string() + " lost: " + why);
    } else if (!why.empty()) {
      note("connect", why);
    }
    phase = Phase::Idle;
    got_hello = false;
    incoming_catalog.reset();
    stats.link_up = false;
    retry_at = Clock::now() + backoff;
    backoff = std::min(backoff * 2, options.reconnect_max);
  }

  void try_connect() {
    refresh_keys(true);
    const bool stream = where.kind == Endpoint::Kind::Tcp;
    UniqueFd fd;
    int err = 0;
    if (!stream) {
      fd.reset(::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
      if (!fd) throw std::runtime_error("socket(AF_UNIX, SOCK_SEQPACKET): " + detail::errno_text(errno));
      const detail::UnixAddress addr(where.path);
      if (addr.error() != 0) {
        err = addr.error();
      } else if (::connect(fd.get(), addr.get(), addr.size()) != 0) {
        err = errno;
      }
    } else {
      addrinfo hints{};
      hints.ai_family = AF_UNSPEC;
      hints.ai_socktype = SOCK_STREAM;
      addrinfo* res = nullptr;
      const std::string port = std::to_string(where.port);
      if (int rc = ::getaddrinfo(where.host.c_str(), port.c_str(), &hints, &res); rc != 0) {
        disconnect("cannot resolve '" + where.host + "': " + ::gai_strerror(rc), false);
        return;
      }
      std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> guard(res, ::freeaddrinfo);
      fd.reset(::socket(res->ai_family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
      if (!fd) throw std::runtime_error("socket(SOCK_STREAM): " + detail::errno_text(errno));
      const int one = 1;
      ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      if (::connect(fd.get(), res->ai_addr, res->ai_addrlen) != 0) err = errno;
    }
    if (err != 0 && err != EINPROGRESS && err != EAGAIN) {
      disconnect("cannot connect to " + where.to_string() + ": " + detail::errno_text(err), false);
      return;
    }
    channel = std::make_unique<Channel>(std::move(fd), stream, "publisher " + where.to_string() +
                                                                   (keys || !stream ? "" : " [UNAUTHENTICATED]"));
    if (keys) channel->guard(std::make_unique<detail::SessionAuth>(*keys, Role::Subscriber));
    if (!keys && stream) {
      detail::log_limited("insecure", options.name + ": UNAUTHENTICATED link to " + where.to_string() + " (--insecure-link)");
    }
    poller.add(channel->fd(), true);
    phase = Phase::Connecting;
    if (err == 0) on_connected();
  }

  void on_connected() {
    if (where.kind == Endpoint::Kind::Unix) {
      ucred cred{};
      socklen_t len = sizeof cred;
      if (::getsockopt(channel->fd(), SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0) {
        disconnect("SO_PEERCRED failed: " + detail::errno_text(errno), false);
        return;
      }
      const auto& ok = options.allowed_uids;
      if (std::find(ok.begin(), ok.end(), cred.uid) == ok.end()) {
        ++stats.peers_rejected;
        disconnect("publisher on " + where.to_string() + " runs as uid " + std::to_string(cred.uid) +
                       ", which is not in the allow-list",
                   false);
        return;
      }
    }
    phase = Phase::Handshake;
    Hello hello = our_hello();
    if (channel->guard() != nullptr) channel->guard()->announce(hello);
    channel->send(hello, stats);
    channel->last_rx = Clock::now();  // the handshake timeout counts from here
  }

  Hello our_hello() const { return detail::make_hello(Role::Subscriber, table.catalog(), our_hash, options); }

  // The publisher's catalog is complete: from now on its ids are the ones this process reads.
  void take_catalog(std::shared_ptr<const Catalog> taken) {
    our_hash = taken->hash();
    set_active_catalog(taken);  // the decoder checks ids against the active catalog
    table = SignalTable(std::move(taken));
    ++catalog_changes;
    ++stats.catalogs_taken;
    changed = true;
    detail::log_limited("catalog-taken", options.name + ": using " + table.catalog().source() + " (" +
                                             std::to_string(table.size()) + " signals)", LogLevel::Info);
  }

  void refuse(CloseReason reason, const std::string& why) {
    ++stats.handshakes_refused;
    channel->send(Close{reason, why.substr(0, kMaxTextBytes)}, stats);
    std::string ignored;
    channel->flush(stats, ignored);
    pending_disconnect = PendingDisconnect{"refused publisher " + where.to_string() + ": " + why, false};
  }

  // The frame is ours (on_frame takes it by value): its texts move into the table.
  void apply(std::vector<SignalUpdate>& updates, const Frame& frame) {
    for (auto& u : updates) {
      // The decoder checked the id. An entry without text clears any text the signal had.
      if (table.set(u.id, SignalState{u.value, u.status, u.has_text ? std::move(u.text) : std::string()})) {
        ++stats.signal_updates_applied;
        changed = true;
      }
    }
    sender_time_ns = frame.timestamp_ns;
    last_applied_seq = frame.sequence;
  }

  // Returns false if the channel was closed while handling the frame.
  bool on_frame(Frame&& frame) {
    if (observer) observer(frame);
    if (auto* close = std::get_if<Close>(&frame.message)) {
      const bool was_live = phase == Phase::Live;
      if (close->reason != CloseReason::Normal) ++stats.handshakes_refused;
      pending_disconnect = PendingDisconnect{"publisher closed the link: " + std::string(to_string(close->reason)) +
                                                 (close->text.empty() ? "" : ": " + close->text),
                                             was_live};
      return false;
    }
    if (!got_hello) {
      auto* hello = std::get_if<Hello>(&frame.message);
      if (hello == nullptr) {
        refuse(CloseReason::ProtocolError,
               "expected HELLO first, got " + std::string(to_string(type_of(frame.message))));
        return false;
      }
      CloseReason reason{};
      if (auto why = detail::check_hello(*hello, Role::Publisher, reason); !why.empty()) {
        refuse(reason, why);
        return false;
      }
      if (auto why = detail::start_session(channel->guard(), *hello); !why.empty()) {
        refuse(CloseReason::Authentication, why);
        return false;
      }
      switch (detail::agree_catalogs(hello->catalog_hash, our_hash, options.take_peer_catalog)) {
        case detail::CatalogAgreement::Same: break;
        case detail::CatalogAgreement::Refuse:
          refuse(CloseReason::CatalogMismatch, detail::catalog_mismatch(*hello, our_hello()));
          return false;
        case detail::CatalogAgreement::Transfer:
          incoming_catalog.emplace(hello->catalog_hash, "catalog sent by " + (hello->name.empty() ? std::string("the publisher") : hello->name) +
                                                            " (" + hello->catalog_source + ")");
          break;
      }
      got_hello = true;
      peer_heartbeat = std::chrono::milliseconds(hello->heartbeat_period_ms);
      if (!hello->name.empty()) channel->set_label(hello->name + " at " + where.to_string());
      return true;
    }
    if (auto* piece = std::get_if<CatalogChunk>(&frame.message)) {
      if (!incoming_catalog) {
        refuse(CloseReason::ProtocolError, "CATALOG without a catalog mismatch to resolve");
        return false;
      }
      if (auto why = incoming_catalog->add(*piece); !why.empty()) {
        refuse(CloseReason::ProtocolError, why);
        return false;
      }
      if (incoming_catalog->complete()) {
        take_catalog(incoming_catalog->take());
        incoming_catalog.reset();
      }
      return true;
    }
    if (incoming_catalog) {
      refuse(CloseReason::ProtocolError, std::string(to_string(type_of(frame.message))) +
                                             " before the publisher's catalog was complete");
      return false;
    }
    if (auto* snap = std::get_if<Snapshot>(&frame.message)) {
      apply(snap->signals, frame);
      if (snap->complete && phase != Phase::Live) {
        phase = Phase::Live;
        stats.link_up = true;
        ++stats.connects;
        if (ever_live) ++stats.reconnects;
        ever_live = true;
        backoff = options.reconnect_min;
        last_error.clear();
      }
      return true;
    }
    if (auto* delta = std::get_if<Delta>(&frame.message)) {
      if (phase != Phase::Live) {
        refuse(CloseReason::ProtocolError, "DELTA before the SNAPSHOT completed");
        return false;
      }
      apply(delta->signals, frame);
      return true;
    }
    if (std::holds_alternative<Heartbeat>(frame.message)) return true;
    if (auto* st = std::get_if<Status>(&frame.message)) {
      publisher_status = *st;
      return true;
    }
    // HELLO twice: count, log and ignore.
    ++stats.bad_frames.malformed;
    detail::log_limited("unexpected", options.name + ": ignored unexpected " +
                                          std::string(to_string(type_of(frame.message))) + " from the publisher");
    return true;
  }

  std::chrono::milliseconds loss_threshold() const {
    return std::max(options.heartbeat_period, peer_heartbeat) * options.missed_heartbeats_for_loss;
  }

  void service(const std::vector<int>& ready) {
    refresh_keys(false);
    const auto now = Clock::now();
    if (!channel) {
      if (now >= retry_at) try_connect();
      return;
    }
    const bool readable = std::find(ready.begin(), ready.end(), channel->fd()) != ready.end();
    if (phase == Phase::Connecting) {
      if (readable) {
        int err = 0;
        socklen_t len = sizeof err;
        ::getsockopt(channel->fd(), SOL_SOCKET, SO_ERROR, &err, &len);
        if (err != 0) {
          disconnect("cannot connect to " + where.to_string() + ": " + detail::errno_text(err), false);
          return;
        }
        on_connected();
        if (!channel) return;
      } else if (now - channel->last_tx > loss_threshold()) {
        disconnect("connect to " + where.to_string() + " timed out", false);
        return;
      } else {
        return;
      }
    }
    if (readable) {
      auto result = channel->receive(stats, [&](Frame&& f) { return on_frame(std::move(f)); });
      if (pending_disconnect) {
        auto pd = std::move(*pending_disconnect);
        pending_disconnect.reset();
        disconnect(pd.why, pd.loss);
        return;
      }
      if (result.outcome == detail::ReadOutcome::Fatal) {
        const bool was_live = phase == Phase::Live;
        ++stats.handshakes_refused;
        channel->send(Close{result.reason, result.detail.substr(0, kMaxTextBytes)}, stats);
        std::string ignored;
        channel->flush(stats, ignored);
        disconnect(result.detail, was_live);
        return;
      }
      if (result.outcome == detail::ReadOutcome::PeerClosed) {
        disconnect(result.detail, phase == Phase::Live);
        return;
      }
    }
    if (phase == Phase::Live && !channel->has_pending()) {
      if (pending_status) {
        channel->send(*pending_status, stats);
        pending_status.reset();
      } else if (now - channel->last_tx >= options.heartbeat_period) {
        channel->send(Heartbeat{}, stats);
      }
    }
    std::string error;
    if (!channel->flush(stats, error)) {
      disconnect(error, phase == Phase::Live);
      return;
    }
    if (now - channel->last_rx > loss_threshold()) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - channel->last_rx).count();
      const bool live = phase == Phase::Live;
      disconnect((live ? "no message for " : "no handshake for ") + std::to_string(ms) + " ms", live);
      return;
    }
    poller.modify(channel->fd(), channel->has_pending());
  }
};

Subscriber::Subscriber(const Endpoint& where, LinkOptions options)
    : impl_(std::make_unique<Impl>(where, std::move(options))) {}
Subscriber::~Subscriber() {
  if (impl_ && impl_->channel && impl_->phase == Impl::Phase::Live) {
    impl_->channel->send(Close{CloseReason::Normal, "view shutting down"}, impl_->stats);
    std::string ignored;
    impl_->channel->flush(impl_->stats, ignored);
  }
}
Subscriber::Subscriber(Subscriber&&) noexcept = default;
Subscriber& Subscriber::operator=(Subscriber&&) noexcept = default;

bool Subscriber::poll(std::chrono::milliseconds timeout) {
  auto& im = *impl_;
  im.changed = false;
  const auto deadline = Clock::now() + timeout;
  int wait_ms = 0;
  for (;;) {
    im.service(im.poller.wait(wait_ms));
    if (im.changed) return true;
    const auto now = Clock::now();
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now).count();
    if (left <= 0) return false;
    long long cap = im.options.heartbeat_period.count();
    if (!im.channel) {
      cap = std::min<long long>(cap, std::max<long long>(
          0, std::chrono::ceil<std::chrono::milliseconds>(im.retry_at - now).count()));
    }
    wait_ms = static_cast<int>(std::min<long long>(left, cap));
  }
}

bool Subscriber::link_up() const { return impl_->phase == Impl::Phase::Live; }
const SignalState& Subscriber::get(SignalId id) const {
  return impl_->table.get(id);
}
const SignalTable& Subscriber::signals() const { return impl_->table; }
const Catalog& Subscriber::catalog() const { return impl_->table.catalog(); }
std::uint64_t Subscriber::catalog_changes() const { return impl_->catalog_changes; }
std::uint64_t Subscriber::state_version() const { return impl_->table.version(); }
std::int64_t Subscriber::last_sender_time_ns() const { return impl_->sender_time_ns; }
std::uint64_t Subscriber::last_sequence_applied() const { return impl_->last_applied_seq; }

void Subscriber::send_status(std::uint64_t frames_rendered, std::uint32_t fault_flags) {
  auto& im = *impl_;
  im.pending_status = Status{frames_rendered, im.last_applied_seq, fault_flags};
  if (im.phase == Impl::Phase::Live && !im.channel->has_pending()) {
    im.channel->send(*im.pending_status, im.stats);
    im.pending_status.reset();
    std::string error;
    if (!im.channel->flush(im.stats, error)) im.disconnect(error, true);
  }
}

std::optional<Status> Subscriber::publisher_status() const { return impl_->publisher_status; }

LinkStats Subscriber::stats() const { return impl_->stats; }
int Subscriber::wait_fd() const { return impl_->poller.fd(); }
std::string Subscriber::last_error() const { return impl_->last_error; }
void Subscriber::set_frame_observer(FrameObserver observer) { impl_->observer = std::move(observer); }

}  // namespace meter::protocol
