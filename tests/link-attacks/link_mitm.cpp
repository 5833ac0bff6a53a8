// link_mitm: a man in the middle of the controller-to-view link, for the attack tests. It listens
// where the view connects (--front), connects to the real controller (--back) for every view
// connection, relays frames both ways, and runs its attacks in order, each once the session and
// the view's answer to the previous attack have had --settle-ms. It holds no key: what it sends is what an attacker on the
// path can send. Every attack is one line on stdout ("attack NAME: what; values ..."): the values
// it tried to make the view draw, so the test can check that none was drawn.
//
//   link_mitm --front EP --back EP --attacks modify,replay,... [--settle-ms 400] [--blackhole-ms 900]
//
// Attacks (on the controller's frames unless said): modify (one byte of a DELTA's value, CRC
// fixed), replay (an older DELTA of this session again), reorder (a DELTA held back behind the
// next frame), drop (a DELTA), forge (a DELTA with the attacker's value, a guessed tag), strip (a
// DELTA without its MAC, then an untagged forged one), version (a DELTA claiming protocol version
// 2), truncate (half a DELTA), flood (500 forged DELTAs), session (a whole recorded session played
// to a new view connection), hello (the view's HELLO without key and tag: the downgrade at the
// handshake), blackhole (nothing relayed for --blackhole-ms). After the last attack it relays
// until the view is back in sync, then exits 0.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "meter/protocol/endpoint.hpp"
#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/wire.hpp"

using namespace meter::protocol;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;

namespace {

constexpr double kAttackerSpeed = 222.0;  // never on the real drive (at most 100 km/h)

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "link_mitm: %s\n", what.c_str());
  std::exit(2);
}

// A socket of the endpoint's kind and its address (TCP: loopback, the endpoint's port).
int socket_for(const Endpoint& ep, sockaddr_storage& addr, socklen_t& len) {
  addr = {};
  if (ep.kind == Endpoint::Kind::Unix) {
    auto& a = reinterpret_cast<sockaddr_un&>(addr);
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof a.sun_path, "%s", ep.path.c_str());
    len = sizeof a;
    return ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  }
  auto& a = reinterpret_cast<sockaddr_in&>(addr);
  a.sin_family = AF_INET;
  a.sin_port = htons(ep.port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  len = sizeof a;
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

int listen_on(const Endpoint& ep) {
  sockaddr_storage addr;
  socklen_t len = 0;
  const int fd = socket_for(ep, addr, len);
  if (ep.kind == Endpoint::Kind::Unix) ::unlink(ep.path.c_str());
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), len) != 0 || ::listen(fd, 8) != 0) die("cannot listen on " + ep.to_string());
  return fd;
}

// -1 if nothing listens there (the controller is down): the view's connection then ends too.
int connect_to(const Endpoint& ep) {
  sockaddr_storage addr;
  socklen_t len = 0;
  const int fd = socket_for(ep, addr, len);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), len) == 0) return fd;
  ::close(fd);
  return -1;
}

// One socket of a session: whole frames in (datagrams, or reassembled from the stream), bytes out.
struct Pipe {
  int fd = -1;
  bool stream = false;
  StreamAssembler assembler;
  bool closed = false;

  std::vector<Bytes> read_frames() {
    std::vector<Bytes> out;
    Bytes buf(kMaxFrameSize + 1);
    const ssize_t n = ::recv(fd, buf.data(), buf.size(), MSG_DONTWAIT);
    if (n <= 0) {
      if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) closed = true;
      return out;
    }
    buf.resize(static_cast<std::size_t>(n));
    if (!stream) {
      out.push_back(std::move(buf));
      return out;
    }
    assembler.append(buf);
    while (auto r = assembler.next()) {
      if (r->error != DecodeError::None) die("the real peers sent a bad frame: " + r->detail);
      out.emplace_back(r->bytes.begin(), r->bytes.end());
    }
    return out;
  }
  void write(const Bytes& b) {
    if (fd >= 0 && !closed && ::send(fd, b.data(), b.size(), MSG_NOSIGNAL) < 0) closed = true;
  }
  void close() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    closed = true;
  }
};

std::uint8_t type_of_bytes(const Bytes& b) { return b.size() > 5 ? b[5] : 0; }
std::uint64_t seq_of(const Bytes& b) {
  std::uint64_t s = 0;
  for (int i = 7; i >= 0; --i) s = s << 8 | b[12 + i];
  return s;
}
void fix_crc(Bytes& b) {
  std::uint32_t len = 0;
  for (int i = 3; i >= 0; --i) len = len << 8 | b[8 + i];
  std::uint32_t crc = crc32c(std::span(b).first(28));
  crc = crc32c(std::span(b).subspan(kHeaderSize, len), crc);
  for (int i = 0; i < 4; ++i) b[28 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
}

// A DELTA setting the speed to the attacker's value at `seq`, tagged with a key of its own
// choosing (`tagged`) or untagged.
Bytes forged_delta(std::uint64_t seq, bool tagged, std::mt19937_64& rng) {
  FrameKey guess;
  for (auto& b : guess.bytes) b = static_cast<std::uint8_t>(rng());
  const Frame f{seq, 0, Delta{{SignalUpdate{sig::kSpeed, SignalStatus::Valid, kAttackerSpeed, false, {}}}}};
  return encode(f, tagged ? &guess : nullptr);
}

struct Mitm {
  Endpoint front_ep, back_ep;
  std::deque<std::string> attacks;
  std::chrono::milliseconds settle{400}, blackhole{900};
  int listener = -1;
  Pipe front, back;
  Clock::time_point session_start, last_attack;
  std::vector<Bytes> history;           // this session's frames from the controller
  std::vector<Bytes> recorded_session;  // the first session's, for the session replay
  int sessions = 0;
  bool replaying = false;               // a recorded session is being played to the view
  std::optional<Bytes> held;            // reorder: a DELTA waiting behind the next frame
  std::string pending;                  // an attack that takes effect on the next session
  std::mt19937_64 rng{46};
  bool done_attacking = false;

  void log(const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }

  void end_session() {
    front.close();
    back.close();
    history.clear();
    held.reset();
  }

  void start_session(int fd) {
    end_session();
    const bool stream = front_ep.kind == Endpoint::Kind::Tcp;
    front = Pipe{fd, stream, {}, false};
    session_start = Clock::now();
    ++sessions;
    if (pending == "session") {
      log("attack session: the recorded session (" + std::to_string(recorded_session.size()) +
          " frames) played to a new view connection; values " + std::to_string(kAttackerSpeed));
      for (const auto& b : recorded_session) front.write(b);
      pending.clear();
      replaying = true;  // until the view gives up on it
      back = Pipe{-1, stream, {}, true};
      return;
    }
    back = Pipe{connect_to(back_ep), stream, {}, false};
    if (back.fd < 0) back.closed = true;
  }

  // One of the controller's frames, attacked or not, on its way to the view.
  void to_view(Bytes b) {
    if (sessions == 1 && recorded_session.size() < 200) recorded_session.push_back(b);
    history.push_back(b);
    if (held) {
      front.write(b);
      front.write(*held);
      held.reset();
      return;
    }
    const bool delta = type_of_bytes(b) == static_cast<std::uint8_t>(MessageType::Delta);
    // Settled: the session, and the view's answer to the last attack (often a closed connection,
    // noticed here only when the view's side is read), have had --settle-ms.
    const bool due = delta && !attacks.empty() && pending.empty() && Clock::now() - session_start >= settle &&
                     Clock::now() - last_attack >= settle;
    if (!due) {
      front.write(b);
      return;
    }
    const std::string a = attacks.front();
    attacks.pop_front();
    last_attack = Clock::now();
    attack(a, std::move(b));
  }

  void attack(const std::string& a, Bytes b) {
    const std::uint64_t seq = seq_of(b);
    if (a == "modify") {
      b[kHeaderSize + 4 + 4 + 6] ^= 0x40;  // a high byte of the first entry's value
      fix_crc(b);
      double v = 0;
      std::memcpy(&v, b.data() + kHeaderSize + 8, sizeof v);
      std::ostringstream s;
      s.precision(17);
      s << v;
      log("attack modify: seq " + std::to_string(seq) + " value byte flipped, CRC fixed; values " + s.str());
      front.write(b);
    } else if (a == "replay") {
      front.write(b);
      const Bytes old = history.size() > 3 ? history[history.size() - 3] : history.front();
      log("attack replay: seq " + std::to_string(seq_of(old)) + " sent again after seq " + std::to_string(seq));
      front.write(old);
    } else if (a == "reorder") {
      log("attack reorder: seq " + std::to_string(seq) + " held behind the next frame");
      held = std::move(b);
    } else if (a == "drop") {
      log("attack drop: seq " + std::to_string(seq) + " dropped");
    } else if (a == "forge") {
      front.write(b);
      log("attack forge: DELTA seq " + std::to_string(seq + 1) + " with a guessed tag; values " + std::to_string(kAttackerSpeed));
      front.write(forged_delta(seq + 1, true, rng));
    } else if (a == "strip") {
      const auto r = decode(b);
      log("attack strip: seq " + std::to_string(seq) + " without its MAC, then an untagged forged DELTA; values " +
          std::to_string(kAttackerSpeed));
      front.write(encode(r.frame));
      front.write(forged_delta(seq + 1, false, rng));
    } else if (a == "version") {
      b[4] = 2;
      fix_crc(b);
      log("attack version: seq " + std::to_string(seq) + " claims protocol version 2");
      front.write(b);
    } else if (a == "truncate") {
      log("attack truncate: seq " + std::to_string(seq) + " cut to " + std::to_string(b.size() / 2) + " bytes");
      b.resize(b.size() / 2);
      front.write(b);
    } else if (a == "flood") {
      front.write(b);
      log("attack flood: 500 forged DELTAs; values " + std::to_string(kAttackerSpeed));
      for (int i = 0; i < 500; ++i) front.write(forged_delta(seq + 1 + (i % 3), true, rng));
    } else if (a == "session" || a == "hello") {
      front.write(b);
      pending = a;  // on the next view connection
      log("attack " + a + ": ending this session; the next one is attacked");
      end_session();
    } else if (a == "blackhole") {
      log("attack blackhole: nothing relayed for " + std::to_string(blackhole.count()) + " ms");
      const auto until = Clock::now() + blackhole;
      while (Clock::now() < until) ::usleep(10000);
      end_session();
    } else {
      die("unknown attack '" + a + "'");
    }
  }

  // The view's frames on their way to the controller; `hello` strips the HELLO's key and tag.
  void to_controller(Bytes b) {
    if (pending == "hello" && type_of_bytes(b) == static_cast<std::uint8_t>(MessageType::Hello)) {
      auto r = decode(b);
      auto& h = std::get<Hello>(r.frame.message);
      h.key_id = 0;
      h.nonce = {};
      log("attack hello: the view's HELLO sent without key id and tag (a downgrade to no MAC)");
      b = encode(r.frame);
      pending.clear();
    }
    if (back.fd >= 0) back.write(b);
  }

  int run() {
    listener = listen_on(front_ep);
    log("listening on " + front_ep.to_string());
    Clock::time_point calm_since = Clock::now();
    for (;;) {
      pollfd fds[3] = {{listener, POLLIN, 0}, {front.fd, POLLIN, 0}, {back.fd, POLLIN, 0}};
      ::poll(fds, 3, 20);
      if (fds[0].revents & POLLIN) start_session(::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC));
      if (front.fd >= 0 && (fds[1].revents & (POLLIN | POLLHUP))) {
        for (auto& b : front.read_frames()) to_controller(std::move(b));
      }
      if (back.fd >= 0 && (fds[2].revents & (POLLIN | POLLHUP))) {
        for (auto& b : back.read_frames()) to_view(std::move(b));
      }
      if (replaying && front.closed) replaying = false;
      if (front.closed != back.closed && !replaying) end_session();  // one side left: so does the other
      // Done: no attack left and a session relayed calmly for twice the settle time.
      if (!attacks.empty() || !pending.empty() || front.closed) calm_since = Clock::now();
      if (Clock::now() - calm_since > 2 * settle) {
        log("done: relayed calmly after the last attack");
        return 0;
      }
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  Mitm m;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string opt = argv[i], val = argv[i + 1];
    if (opt == "--front") {
      m.front_ep = Endpoint::parse(val);
    } else if (opt == "--back") {
      m.back_ep = Endpoint::parse(val);
    } else if (opt == "--attacks") {
      std::stringstream s(val);
      for (std::string a; std::getline(s, a, ',');) m.attacks.push_back(a);
    } else if (opt == "--settle-ms") {
      m.settle = std::chrono::milliseconds(std::stoi(val));
    } else if (opt == "--blackhole-ms") {
      m.blackhole = std::chrono::milliseconds(std::stoi(val));
    } else {
      die("unknown option " + opt);
    }
  }
  if (m.attacks.empty()) die("usage: link_mitm --front EP --back EP --attacks a,b,... [--settle-ms N] [--blackhole-ms N]");
  return m.run();
}
