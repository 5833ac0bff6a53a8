// meter_protocol_bench: the cost of the controller-to-view link, measured side by side in one run.
//   1. encode / decode / CRC throughput on plain bytes (no sockets);
//   2. bytes on the wire per change: per-peer DELTA vs resending the full SNAPSHOT;
//   3. DELTA latency from send (sender timestamp, taken when the frame is encoded) to apply (the
//      Subscriber's poll() returning) between two processes (fork), over a Unix SOCK_SEQPACKET
//      socket and over TCP loopback, paced so nothing coalesces;
//   4. the link's MAC (docs/security.md): per DELTA and per HEARTBEAT on plain bytes, and the CPU
//      both processes spend per DELTA with and without it, side by side in one run.
// Usage: meter_protocol_bench [samples]   (default 2000 latency samples per transport)
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"

using namespace meter::protocol;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

volatile std::size_t g_sink = 0;  // keeps the optimiser from dropping the measured work

struct Rate {
  double per_second;
  double ns_each;
};

template <typename F>
Rate measure(std::size_t iterations, F&& body) {
  for (std::size_t i = 0; i < iterations / 10; ++i) body(i);  // warm-up
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < iterations; ++i) body(i);
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  return {static_cast<double>(iterations) / s, s * 1e9 / static_cast<double>(iterations)};
}

// The same on this thread's CPU clock: the time the work took on a core, not the time the shared
// machine let it wait. The MAC's goal is a CPU cost.
template <typename F>
Rate measure_cpu(std::size_t iterations, F&& body) {
  const auto cpu_now = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) / 1e9;
  };
  for (std::size_t i = 0; i < iterations / 10; ++i) body(i);  // warm-up
  const double t0 = cpu_now();
  for (std::size_t i = 0; i < iterations; ++i) body(i);
  const double s = cpu_now() - t0;
  return {static_cast<double>(iterations) / s, s * 1e9 / static_cast<double>(iterations)};
}

Frame typical_delta(std::size_t i) {
  // What a 60 Hz tick usually carries: speed, rpm, one lamp.
  return Frame{i + 1, static_cast<std::int64_t>(i),
               Delta{{{sig::kSpeed, SignalStatus::Valid, 50.0 + static_cast<double>(i % 100), false, ""},
                      {sig::kEngineSpeed, SignalStatus::Valid, 2000.0 + static_cast<double>(i % 1000), false, ""},
                      {sig::kTurnLeft, SignalStatus::Valid, static_cast<double>(i % 2), false, ""}}}};
}

Frame full_snapshot(std::size_t i) {
  Snapshot s;
  for (const auto& info : catalog()) s.signals.push_back({info.id, SignalStatus::Valid, info.min, false, ""});
  return Frame{i + 1, 0, std::move(s)};
}

void throughput() {
  std::printf("== encode/decode on plain bytes (no sockets)\n");
  constexpr std::size_t kN = 1'000'000;
  std::vector<std::uint8_t> buf;
  buf.reserve(kMaxFrameSize);
  const auto enc = measure(kN, [&](std::size_t i) {
    buf.clear();
    encode(typical_delta(i), buf);
    g_sink = g_sink + buf.size();
  });
  const auto delta_bytes = encode(typical_delta(7));
  const auto dec = measure(kN, [&](std::size_t) {
    const auto r = decode(delta_bytes);
    g_sink = g_sink + r.frame_size;
  });
  const auto both = measure(kN, [&](std::size_t i) {
    buf.clear();
    encode(typical_delta(i), buf);
    const auto r = decode(buf);
    g_sink = g_sink + r.frame_size;
  });
  const auto snap_bytes = encode(full_snapshot(1));
  const auto snap = measure(kN / 10, [&](std::size_t i) {
    buf.clear();
    encode(full_snapshot(i), buf);
    const auto r = decode(buf);
    g_sink = g_sink + r.frame_size;
  });
  std::vector<std::uint8_t> block(64 * 1024, 0x5A);
  const auto crc = measure(20'000, [&](std::size_t i) {
    block[0] = static_cast<std::uint8_t>(i);
    g_sink = g_sink + crc32c(block);
  });
  std::printf("  DELTA (3 signals, %zu B)  encode          %10.0f msg/s  %7.0f ns/msg\n", delta_bytes.size(),
              enc.per_second, enc.ns_each);
  std::printf("  DELTA (3 signals, %zu B)  decode          %10.0f msg/s  %7.0f ns/msg\n", delta_bytes.size(),
              dec.per_second, dec.ns_each);
  std::printf("  DELTA (3 signals, %zu B)  encode+decode   %10.0f msg/s  %7.0f ns/msg\n", delta_bytes.size(),
              both.per_second, both.ns_each);
  std::printf("  SNAPSHOT (%zu signals, %zu B) encode+decode %8.0f msg/s  %7.0f ns/msg\n", catalog().size(),
              snap_bytes.size(), snap.per_second, snap.ns_each);
  std::printf("  CRC-32C (slicing-by-8)                    %10.1f MB/s\n",
              crc.per_second * static_cast<double>(block.size()) / 1e6);
  std::printf("  ratio: full SNAPSHOT bytes / typical DELTA bytes = %.1fx; encode+decode time ratio = %.1fx\n",
              static_cast<double>(snap_bytes.size()) / static_cast<double>(delta_bytes.size()),
              snap.ns_each / both.ns_each);
}

// The MAC alone and within encode/decode, per DELTA (the typical 3-signal tick) and HEARTBEAT.
void mac_cost() {
  std::printf("== MAC (keyed BLAKE2b-128, libsodium) on plain bytes, CPU time per frame\n");
  constexpr std::size_t kN = 1'000'000;
  FrameKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = static_cast<std::uint8_t>(i * 7 + 1);
  std::vector<std::uint8_t> buf;
  buf.reserve(kMaxFrameSize);
  for (const bool heartbeat : {false, true}) {
    const auto frame = [&](std::size_t i) { return heartbeat ? Frame{i + 1, 0, Heartbeat{}} : typical_delta(i); };
    const auto plain = encode(frame(7));
    const auto tagged = encode(frame(7), &key);
    const auto tag_only = measure_cpu(kN, [&](std::size_t i) {
      buf.assign(plain.begin(), plain.end());
      buf[12] = static_cast<std::uint8_t>(i);  // another sequence number each time
      g_sink = g_sink + frame_tag(buf, key)[0];
    });
    const auto verify = measure_cpu(kN, [&](std::size_t) { g_sink = g_sink + (frame_tag_matches(tagged, key) ? 1 : 0); });
    const auto enc_plain = measure_cpu(kN, [&](std::size_t i) {
      buf.clear();
      encode(frame(i), buf);
      g_sink = g_sink + buf.size();
    });
    const auto enc_tagged = measure_cpu(kN, [&](std::size_t i) {
      buf.clear();
      encode(frame(i), buf, &key);
      g_sink = g_sink + buf.size();
    });
    const char* name = heartbeat ? "HEARTBEAT" : "DELTA (3 signals)";
    std::printf("  %-18s %3zu B -> %3zu B tagged: tag %6.0f ns, verify %6.0f ns, encode %6.0f -> %6.0f ns "
                "(goal: MAC <= 1000 ns per frame: %s)\n",
                name, plain.size(), tagged.size(), tag_only.ns_each, verify.ns_each, enc_plain.ns_each,
                enc_tagged.ns_each, std::max(tag_only.ns_each, verify.ns_each) <= 1000 ? "met" : "MISSED");
  }
}

// A key file for the bench's authenticated runs (mode 0600, removed at exit).
std::string bench_key_file() {
  static const std::string path = "/tmp/meter-bench-" + std::to_string(::getpid()) + ".keys";
  static const bool written = [] {
    if (FILE* f = std::fopen(path.c_str(), "w")) {
      std::fprintf(f, "1 ");
      for (int i = 0; i < 32; ++i) std::fprintf(f, "%02x", (i * 37 + 11) & 0xFF);
      std::fprintf(f, "\n");
      std::fclose(f);
    }
    ::chmod(path.c_str(), 0600);
    return std::atexit([] { std::remove(path.c_str()); }) == 0;
  }();
  (void)written;
  return path;
}

LinkOptions bench_options(const char* name, bool mac) {
  LinkOptions o;
  o.name = name;
  if (mac) {
    o.key_file = bench_key_file();
  } else {
    o.insecure_link = true;  // the comparison's unauthenticated side (a lab link)
  }
  return o;
}

double cpu_seconds(int who) {
  rusage ru{};
  ::getrusage(who, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e6;
}

struct Latency {
  std::vector<double> us;
  std::size_t lost = 0;
  double publisher_cpu_s = 0, subscriber_cpu_s = 0;  // CPU of each end over the whole run
};

double pct(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto idx = static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(idx, v.size() - 1)];
}

// Child: the controller. Sends `samples` paced DELTAs once the view is in sync.
// `sleep_paced`: sleep between DELTAs instead of polling (the CPU comparison: only the link's
// own work is counted, not a busy wait).
[[noreturn]] void run_publisher(const Endpoint& where, int port_pipe, int samples, bool mac, bool sleep_paced) {
  int rc = 0;
  try {
    Publisher pub(where, bench_options("bench-controller", mac));
    const std::uint16_t port = pub.endpoint().port;
    if (::write(port_pipe, &port, sizeof port) != sizeof port) std::_Exit(3);
    ::close(port_pipe);
    const auto give_up = Clock::now() + 10s;
    while (pub.peer_count() == 0 && Clock::now() < give_up) pub.poll(1ms);
    pub.poll(20ms);  // let the snapshot land before the timed part
    for (int i = 1; i <= samples; ++i) {
      pub.set(sig::kSpeed, i, SignalStatus::Valid);
      pub.poll(0ms);  // encode + send now: the timestamp in the frame is the send time
      // Pace at ~2 kHz, well beyond a 60 Hz display but with no coalescing of consecutive values.
      const auto until = Clock::now() + 500us;
      if (sleep_paced) std::this_thread::sleep_until(until);
      while (Clock::now() < until) pub.poll(0ms);
    }
    const auto linger = Clock::now() + 5s;
    while (pub.peer_count() > 0 && Clock::now() < linger) pub.poll(5ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench publisher: %s\n", e.what());
    rc = 1;
  }
  std::_Exit(rc);
}

Latency run_pair(Endpoint where, int samples, bool mac, bool sleep_paced = false) {
  int fds[2];
  if (::pipe(fds) != 0) std::exit(1);
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fds[0]);
    run_publisher(where, fds[1], samples, mac, sleep_paced);
  }
  ::close(fds[1]);
  std::uint16_t port = 0;
  if (::read(fds[0], &port, sizeof port) != sizeof port) {
    std::fprintf(stderr, "bench: publisher failed to start on %s\n", where.to_string().c_str());
    std::exit(1);
  }
  ::close(fds[0]);
  if (where.kind == Endpoint::Kind::Tcp) where.port = port;

  Latency lat;
  const double self_before = cpu_seconds(RUSAGE_SELF), children_before = cpu_seconds(RUSAGE_CHILDREN);
  {
    Subscriber sub(where, bench_options("bench-view", mac));
    double last = 0;
    const auto give_up = Clock::now() + 30s;
    while (last < samples && Clock::now() < give_up) {
      if (!sub.poll(5ms)) continue;
      const std::int64_t applied = now_ns();  // the change is in our state now
      const double v = sub.get(sig::kSpeed).value;
      if (v >= 1 && v != last) {
        // Two DELTAs applied in one poll(): only the newer one is timed.
        lat.lost += static_cast<std::size_t>(v - last - 1);
        lat.us.push_back(static_cast<double>(applied - sub.last_sender_time_ns()) / 1000.0);
        last = v;
      }
    }
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) std::fprintf(stderr, "bench: publisher exited badly\n");
  lat.subscriber_cpu_s = cpu_seconds(RUSAGE_SELF) - self_before;
  lat.publisher_cpu_s = cpu_seconds(RUSAGE_CHILDREN) - children_before;
  return lat;
}

void print_latency(const char* name, const Latency& l, int samples) {
  std::printf("  %-22s n=%zu/%d  p50 %7.1f us  p90 %7.1f us  p99 %7.1f us  max %8.1f us  not timed %zu\n", name,
              l.us.size(), samples, pct(l.us, 50), pct(l.us, 90), pct(l.us, 99), pct(l.us, 100), l.lost);
}

// The link's CPU per DELTA (both processes) with and without the MAC, alternating runs so both
// see the same machine load; the lowest of `rounds` runs of each counts.
void link_cpu(const Endpoint& unix_ep, int samples) {
  constexpr int rounds = 5;
  std::printf("== link CPU per DELTA (both processes), %d sleep-paced updates, best of %d runs each\n", samples, rounds);
  for (const bool tcp : {false, true}) {
    double best[2] = {1e9, 1e9};
    for (int r = 0; r < rounds; ++r) {
      for (const bool mac : {false, true}) {
        const auto l = run_pair(tcp ? Endpoint::parse("tcp:127.0.0.1:0") : unix_ep, samples, mac, true);
        if (l.us.empty()) continue;
        best[mac ? 1 : 0] = std::min(best[mac ? 1 : 0], (l.publisher_cpu_s + l.subscriber_cpu_s) * 1e6 / samples);
      }
    }
    std::printf("  %-20s without MAC %6.2f us/DELTA, with MAC %6.2f us/DELTA: ratio %.3f (goal <= 1.02: %s)\n",
                tcp ? "tcp loopback" : "unix SOCK_SEQPACKET", best[0], best[1], best[1] / best[0],
                best[1] / best[0] <= 1.02 ? "met" : "MISSED");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int samples = argc > 1 ? std::atoi(argv[1]) : 2000;
  if (samples < 10) {
    std::fprintf(stderr, "usage: %s [samples >= 10]\n", argv[0]);
    return 2;
  }
  set_log_sink([](std::string_view) {});  // link chatter (peer closed at the end) is not a result
  throughput();
  mac_cost();

  std::printf("== DELTA latency send->apply, two processes, %d paced updates each\n", samples);
  const Endpoint unix_ep = Endpoint::parse("unix:/tmp/meter-bench-" + std::to_string(::getpid()) + ".sock");
  const auto u = run_pair(unix_ep, samples, false);
  const auto um = run_pair(unix_ep, samples, true);
  const auto t = run_pair(Endpoint::parse("tcp:127.0.0.1:0"), samples, true);
  print_latency("unix SOCK_SEQPACKET", u, samples);
  print_latency("unix + MAC", um, samples);
  print_latency("tcp loopback + MAC", t, samples);
  if (!u.us.empty() && !t.us.empty() && !um.us.empty()) {
    std::printf("  ratio tcp/unix: p50 %.2fx  p99 %.2fx; unix MAC/plain: p50 %.2fx\n", pct(t.us, 50) / pct(u.us, 50),
                pct(t.us, 99) / pct(u.us, 99), pct(um.us, 50) / pct(u.us, 50));
  }
  link_cpu(unix_ep, samples);
  return (u.us.empty() || t.us.empty() || um.us.empty()) ? 1 : 0;
}
