#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <stdexcept>

#include "transport/channel.hpp"
#include "transport/clock.hpp"
#include "link/handshake.hpp"
#include "link/key_ring.hpp"
#include "link/session_auth.hpp"
#include "transport/listening_socket.hpp"
#include "transport/log.hpp"
#include "transport/poller.hpp"
#include "transport/unique_fd.hpp"
#include "wire/utf8.hpp"

namespace meter::protocol {

using detail::Channel;
using detail::Clock;
using detail::ListeningSocket;
using detail::UniqueFd;

struct Publisher::Impl {
  struct Peer {
    std::unique_ptr<Channel> channel;
    bool live = false;                 // HELLO accepted, SNAPSHOT sent
    bool closing = false;              // CLOSE queued: flush it, then drop the peer
    bool gone = false;                 // the socket reported EOF or an error
    std::string gone_reason;
    std::vector<std::uint8_t> dirty;   // one flag per catalog entry (attribute-processor style)
    bool any_dirty = false;
    std::chrono::milliseconds peer_heartbeat{0};
    PeerStatus status{0, 0, 0};
    bool status_due = false;           // our fault flags changed since this view last got them
    bool status_stale = false;         // only our counts changed: sent in place of a heartbeat
  };

  Endpoint where;
  LinkOptions options;
  std::uint64_t our_hash;
  std::unique_ptr<detail::KeyRing> keys;  // none: frames carry no MAC
  ListeningSocket listener;
  detail::Poller poller;
  std::vector<Peer> peers;
  SignalTable table;
  std::optional<Status> own_status;  // the controller's health, sent to every view
  LinkStats stats;
  std::string last_error;

  // Checks the options and fills in the defaults before anything binds the endpoint.
  static LinkOptions checked(LinkOptions o, const Endpoint& w) {
    if (auto why = link_security_error(w, o); !why.empty()) throw std::invalid_argument(why);
    if (o.heartbeat_period.count() <= 0) throw std::invalid_argument("heartbeat_period must be > 0 ms");
    if (o.missed_heartbeats_for_loss < 1) throw std::invalid_argument("missed_heartbeats_for_loss must be >= 1");
    if (o.name.empty()) o.name = "publisher";
    if (o.allowed_uids.empty()) o.allowed_uids.push_back(::getuid());
    return o;
  }

  Impl(const Endpoint& w, LinkOptions o)
      : where(w), options(checked(std::move(o), w)),
        our_hash(options.catalog_hash_override.value_or(catalog_hash())),
        keys(options.key_file.empty() ? nullptr : std::make_unique<detail::KeyRing>(options.key_file)),
        listener(where),
        poller(std::max(options.heartbeat_period / 4, std::chrono::milliseconds(1))) {
    where = listener.endpoint();  // TCP port 0 resolved
    poller.add(listener.fd(), false);
    if (!keys && where.kind == Endpoint::Kind::Tcp) {
      detail::log_limited("insecure", options.name + ": UNAUTHENTICATED link on " + where.to_string() +
                                          " (--insecure-link): anyone who can reach the port can drive the display");
    }
  }

  // Takes a changed key file; a connection whose key was removed is closed (it reconnects with a
  // key still held). Checked once a second and before each new connection.
  void refresh_keys(bool now_please) {
    if (!keys || !keys->poll(options.name, now_please)) return;
    for (auto& p : peers) {
      if (!p.closing && p.channel->guard() != nullptr && !p.channel->guard()->keys_held()) {
        refuse(p, CloseReason::Authentication, "a key this connection uses was removed from " + keys->path());
      }
    }
  }

  ~Impl() {
    for (auto& p : peers) {
      if (p.live) {
        p.channel->send(Close{CloseReason::Normal, "publisher shutting down"}, stats);
        std::string ignored;
        p.channel->flush(stats, ignored);
      }
    }
  }

  Peer* find_peer(int fd) {
    for (auto& p : peers) {
      if (p.channel->fd() == fd) return &p;
    }
    return nullptr;
  }

  void accept_all() {
    refresh_keys(true);
    for (;;) {
      UniqueFd fd(::accept4(listener.fd(), nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK));
      if (!fd) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if (errno != EAGAIN && errno != EWOULDBLOCK) {
          detail::log_limited("accept", "accept on " + where.to_string() + " failed: " + detail::errno_text(errno));
        }
        return;
      }
      const bool stream = where.kind == Endpoint::Kind::Tcp;
      std::string label = "view";
      bool allowed = true;
      std::string refusal;
      if (stream) {
        const int one = 1;
        ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);  // DELTAs are tiny: no Nagle
        sockaddr_storage ss{};
        socklen_t len = sizeof ss;
        char host[NI_MAXHOST] = "?", serv[NI_MAXSERV] = "?";
        if (::getpeername(fd.get(), reinterpret_cast<sockaddr*>(&ss), &len) == 0) {
          ::getnameinfo(reinterpret_cast<sockaddr*>(&ss), len, host, sizeof host, serv, sizeof serv,
                        NI_NUMERICHOST | NI_NUMERICSERV);
        }
        label = std::string("view at ") + host + ":" + serv + (keys ? "" : " [UNAUTHENTICATED]");
      } else {
        ucred cred{};
        socklen_t len = sizeof cred;
        if (::getsockopt(fd.get(), SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0) {
          allowed = false;
          refusal = "SO_PEERCRED failed: " + detail::errno_text(errno);
        } else {
          label = "view pid " + std::to_string(cred.pid) + " uid " + std::to_string(cred.uid);
          const auto& ok = options.allowed_uids;
          if (std::find(ok.begin(), ok.end(), cred.uid) == ok.end()) {
            allowed = false;
            refusal = "uid " + std::to_string(cred.uid) + " is not in the allow-list";
          }
        }
      }
      Peer peer;
      peer.channel = std::make_unique<Channel>(std::move(fd), stream, label);
      if (keys) peer.channel->guard(std::make_unique<detail::SessionAuth>(*keys, Role::Publisher));
      peer.dirty.assign(table.size(), 0);
      if (allowed && peers.size() >= options.max_peers) {
        // Bounded resources: every connection costs a buffer and a dirty table.
        last_error = "rejected " + label + ": already serving " + std::to_string(peers.size()) +
                     " connections (max_peers)";
        detail::log_limited("too-many", last_error);
        ++stats.peers_rejected;
        peer.channel->send(Close{CloseReason::ProtocolError, "too many connections"}, stats);
        peer.closing = true;
      } else if (!allowed) {
        ++stats.peers_rejected;
        last_error = "rejected " + label + ": " + refusal;
        detail::log_limited("peer-rejected", last_error);
        peer.channel->send(Close{CloseReason::NotAllowed, refusal.substr(0, kMaxTextBytes)}, stats);
        peer.closing = true;
      } else {
        if (!keys && stream) detail::log_limited("insecure", "accepted " + label + " (--insecure-link)");
        peer.channel->send(hello_for(*peer.channel), stats);
      }
      poller.add(peer.channel->fd(), peer.channel->has_pending());
      peers.push_back(std::move(peer));
    }
  }

  void refuse(Peer& peer, CloseReason reason, const std::string& why) {
    ++stats.handshakes_refused;
    last_error = "refused " + peer.channel->label() + ": " + why;
    detail::log_limited("refused", last_error);
    peer.channel->send(Close{reason, why.substr(0, kMaxTextBytes)}, stats);
    peer.closing = true;
    peer.live = false;
  }

  void on_frame(Peer& peer, Frame&& frame) {
    if (peer.closing) return;
    if (auto* close = std::get_if<Close>(&frame.message)) {
      last_error = peer.channel->label() + " closed the link: " + std::string(to_string(close->reason)) +
                   (close->text.empty() ? "" : ": " + close->text);
      detail::log_limited("peer-close", last_error, close->reason == CloseReason::Normal ? LogLevel::Info : LogLevel::Warning);
      if (close->reason != CloseReason::Normal) ++stats.handshakes_refused;
      peer.closing = true;
      peer.live = false;
      return;
    }
    if (!peer.live) {
      auto* hello = std::get_if<Hello>(&frame.message);
      if (hello == nullptr) {
        refuse(peer, CloseReason::ProtocolError,
               std::string("expected HELLO first, got ") + std::string(to_string(type_of(frame.message))));
        return;
      }
      CloseReason reason{};
      if (auto why = detail::check_hello(*hello, Role::Subscriber, reason); !why.empty()) {
        refuse(peer, reason, why);
        return;
      }
      if (auto why = detail::start_session(peer.channel->guard(), *hello); !why.empty()) {
        refuse(peer, CloseReason::Authentication, why);
        return;
      }
      switch (detail::agree_catalogs(our_hash, hello->catalog_hash, (hello->flags & kHelloTakesCatalog) != 0)) {
        case detail::CatalogAgreement::Same: break;
        case detail::CatalogAgreement::Refuse:
          refuse(peer, CloseReason::CatalogMismatch, detail::catalog_mismatch(our_hello(), *hello));
          return;
        case detail::CatalogAgreement::Transfer:
          // The view takes ours: the catalog goes first, the SNAPSHOT's ids then mean the same there.
          for (const auto& piece : detail::catalog_chunks(table.catalog(), our_hash)) peer.channel->send(piece, stats);
          break;
      }
      if (!hello->name.empty()) peer.channel->set_label(hello->name + " (" + peer.channel->label() + ")");
      peer.peer_heartbeat = std::chrono::milliseconds(hello->heartbeat_period_ms);
      peer.live = true;
      ++stats.connects;
      send_snapshot(peer);
      peer.status_due = own_status.has_value();
      return;
    }
    std::visit(
        [&](auto& m) {
          using T = std::decay_t<decltype(m)>;
          if constexpr (std::is_same_v<T, Status>) {
            peer.status = PeerStatus{m.frames_rendered, m.last_sequence_applied, m.fault_flags};
          } else if constexpr (std::is_same_v<T, Heartbeat>) {
            // last_rx already refreshed by the channel: nothing else to do
          } else {
            // A view never sends HELLO twice, SNAPSHOT or DELTA: count it and ignore it.
            ++stats.bad_frames.malformed;
            detail::log_limited("unexpected", "ignored unexpected " + std::string(to_string(type_of(frame.message))) +
                                                  " from " + peer.channel->label());
          }
        },
        frame.message);
  }

  Hello our_hello() const { return detail::make_hello(Role::Publisher, table.catalog(), our_hash, options); }
  Hello hello_for(const Channel& channel) const {
    Hello hello = our_hello();
    if (channel.guard() != nullptr) channel.guard()->announce(hello);
    return hello;
  }

  SignalUpdate update_for(std::size_t index) const {
    const auto& s = table.states()[index];
    SignalUpdate u;
    const auto& info = table.catalog().signals()[index];
    u.id = info.id;
    u.status = s.status;
    u.value = s.value;
    u.has_text = !s.text.empty() || info.kind == SignalKind::Text;
    u.text = s.text;
    return u;
  }

  // Splits the entries into as many frames as the payload limit needs.
  template <typename Emit>
  void chunked(const std::vector<std::size_t>& indices, Emit&& emit) {
    std::vector<SignalUpdate> batch;
    std::size_t size = kUpdateListOverhead;
    for (std::size_t idx : indices) {
      SignalUpdate u = update_for(idx);
      const std::size_t n = encoded_size(u);
      if (!batch.empty() && size + n > kMaxPayloadSize) {
        emit(std::move(batch), false);
        batch.clear();
        size = kUpdateListOverhead;
      }
      size += n;
      batch.push_back(std::move(u));
    }
    emit(std::move(batch), true);
  }

  void send_snapshot(Peer& peer) {
    std::vector<std::size_t> all(table.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    chunked(all, [&](std::vector<SignalUpdate>&& batch, bool last) {
      peer.channel->send(Snapshot{last, std::move(batch)}, stats);
    });
    std::fill(peer.dirty.begin(), peer.dirty.end(), 0);
    peer.any_dirty = false;
  }

  void send_delta(Peer& peer) {
    std::vector<std::size_t> changed;
    for (std::size_t i = 0; i < peer.dirty.size(); ++i) {
      if (peer.dirty[i] != 0) changed.push_back(i);
    }
    std::fill(peer.dirty.begin(), peer.dirty.end(), 0);
    peer.any_dirty = false;
    if (changed.empty()) return;
    chunked(changed, [&](std::vector<SignalUpdate>&& batch, bool) {
      if (!batch.empty()) peer.channel->send(Delta{std::move(batch)}, stats);
    });
  }

  void mark_dirty(std::size_t index) {
    for (auto& p : peers) {
      if (!p.live) continue;
      if (p.dirty[index] != 0) ++stats.coalesced_updates;  // an unsent value is overwritten
      p.dirty[index] = 1;
      p.any_dirty = true;
    }
  }

  void drop_peer(std::size_t i, const std::string& why, bool loss) {
    Peer& p = peers[i];
    if (loss) {
      ++stats.link_losses;
      last_error = p.channel->label() + ": " + why;
      detail::log_limited("link-lost", "link to " + p.channel->label() + " lost: " + why);
    }
    poller.remove(p.channel->fd());
    peers.erase(peers.begin() + static_cast<std::ptrdiff_t>(i));
  }

  void service(const std::vector<int>& ready) {
    refresh_keys(false);
    for (int fd : ready) {
      if (fd == listener.fd()) {
        accept_all();
        continue;
      }
      Peer* peer = find_peer(fd);
      if (peer == nullptr) continue;
      auto result = peer->channel->receive(stats, [&](Frame&& f) {
        on_frame(*peer, std::move(f));
        return !peer->closing;
      });
      if (result.outcome == detail::ReadOutcome::Fatal && !peer->closing) {
        refuse(*peer, result.reason, result.detail);
      } else if (result.outcome == detail::ReadOutcome::PeerClosed) {
        peer->gone = true;
        peer->gone_reason = result.detail;
      }
    }
    const auto now = Clock::now();
    for (std::size_t i = 0; i < peers.size();) {
      Peer& p = peers[i];
      if (p.gone) {
        drop_peer(i, p.gone_reason, p.live);
        continue;
      }
      if (p.live) {
        // Bounded queue: new DELTAs are built only once the previous batch left; until then the
        // changes stay dirty and later set() calls overwrite them (latest-value semantics).
        if (!p.channel->has_pending()) {
          if (p.any_dirty) send_delta(p);
          if (p.status_due && !p.channel->has_pending()) {
            p.channel->send(*own_status, stats);
            p.status_due = p.status_stale = false;
          }
          if (!p.channel->has_pending() && now - p.channel->last_tx >= options.heartbeat_period) {
            // New counts ride in place of the heartbeat (any message proves the link alive).
            if (p.status_stale) {
              p.channel->send(*own_status, stats);
              p.status_stale = false;
            } else {
              p.channel->send(Heartbeat{}, stats);
            }
          }
        }
      }
      std::string error;
      if (!p.channel->flush(stats, error)) {
        drop_peer(i, error, p.live);
        continue;
      }
      if (p.closing && (!p.channel->has_pending() || now - p.channel->last_tx > loss_threshold(p))) {
        drop_peer(i, "", false);
        continue;
      }
      if (now - p.channel->last_rx > loss_threshold(p)) {
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - p.channel->last_rx).count();
        const bool was_live = p.live;
        drop_peer(i, (was_live ? "no message for " : "no HELLO for ") + std::to_string(ms) + " ms", was_live);
        continue;
      }
      poller.modify(p.channel->fd(), p.channel->has_pending());
      ++i;
    }
    stats.link_up = std::any_of(peers.begin(), peers.end(), [](const Peer& p) { return p.live; });
  }

  std::chrono::milliseconds loss_threshold(const Peer& p) const {
    return std::max(options.heartbeat_period, p.peer_heartbeat) * options.missed_heartbeats_for_loss;
  }
};

namespace {

std::size_t index_or_invalid_argument(const SignalTable& table, SignalId id, const char* who) {
  const auto index = table.index_of(id);
  if (!index) {
    throw std::invalid_argument(std::string(who) + ": signal id " + std::to_string(id) + " is not in the catalog " +
                                table.catalog().source());
  }
  return *index;
}

}  // namespace

Publisher::Publisher(const Endpoint& where, LinkOptions options)
    : impl_(std::make_unique<Impl>(where, std::move(options))) {}
Publisher::~Publisher() = default;
Publisher::Publisher(Publisher&&) noexcept = default;
Publisher& Publisher::operator=(Publisher&&) noexcept = default;

void Publisher::set(SignalId id, double value, SignalStatus status) {
  const std::size_t index = index_or_invalid_argument(impl_->table, id, "Publisher::set");
  if (!std::isfinite(value)) {
    detail::log_limited("nonfinite", "signal " + impl_->table.catalog().signals()[index].name +
                                         ": non-finite value replaced by 0 with status invalid");
    value = 0.0;
    status = SignalStatus::Invalid;
  }
  if (impl_->table.set(id, value, status)) impl_->mark_dirty(index);
}

void Publisher::set_text(SignalId id, std::string_view text, SignalStatus status) {
  const std::size_t index = index_or_invalid_argument(impl_->table, id, "Publisher::set_text");
  if (impl_->table.set_text(id, detail::sanitize_text(text), status)) impl_->mark_dirty(index);
}

void Publisher::send_status(std::uint64_t frames_received, std::uint64_t frames_lost, std::uint32_t fault_flags) {
  const Status s{frames_received, frames_lost, fault_flags};
  if (impl_->own_status == s) return;
  const bool flags_changed = !impl_->own_status || impl_->own_status->fault_flags != fault_flags;
  impl_->own_status = s;
  for (auto& p : impl_->peers) {
    if (!p.live) continue;
    if (flags_changed) p.status_due = true;
    else p.status_stale = true;
  }
}

const SignalState& Publisher::get(SignalId id) const {
  return impl_->table.get(id);
}

void Publisher::poll(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  int wait_ms = 0;
  for (;;) {
    impl_->service(impl_->poller.wait(wait_ms));
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) break;
    wait_ms = static_cast<int>(std::min<long long>(left, impl_->options.heartbeat_period.count()));
  }
}

int Publisher::wait_fd() const { return impl_->poller.fd(); }

std::size_t Publisher::peer_count() const {
  return static_cast<std::size_t>(
      std::count_if(impl_->peers.begin(), impl_->peers.end(), [](const Impl::Peer& p) { return p.live; }));
}

LinkStats Publisher::stats() const { return impl_->stats; }
Endpoint Publisher::endpoint() const { return impl_->where; }
std::string Publisher::last_error() const { return impl_->last_error; }

std::vector<Publisher::PeerStatus> Publisher::peer_status() const {
  std::vector<PeerStatus> out;
  for (const auto& p : impl_->peers) {
    if (p.live) out.push_back(p.status);
  }
  return out;
}

}  // namespace meter::protocol
