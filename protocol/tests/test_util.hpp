// Helpers shared by the protocol unit tests: hand-built frames (so tests can produce exactly the
// malformed input a broken or hostile peer would), temp socket paths, and a pump loop.
#pragma once

#include <stdlib.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"
#include "transport/unix_address.hpp"

namespace meter::protocol::test {

inline void put_le(std::vector<std::uint8_t>& out, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// A frame with any header fields and payload, with a correct CRC unless told otherwise.
inline std::vector<std::uint8_t> raw_frame(std::uint8_t type, const std::vector<std::uint8_t>& payload,
                                           std::uint64_t seq = 1, std::uint8_t version = kProtocolVersion,
                                           std::uint16_t flags = 0, std::uint32_t magic = kMagic) {
  std::vector<std::uint8_t> f;
  put_le(f, magic, 4);
  f.push_back(version);
  f.push_back(type);
  put_le(f, flags, 2);
  put_le(f, payload.size(), 4);
  put_le(f, seq, 8);
  put_le(f, 12345, 8);
  std::uint32_t crc = crc32c(std::span(f).first(28));
  crc = crc32c(payload, crc);
  put_le(f, crc, 4);
  f.insert(f.end(), payload.begin(), payload.end());
  return f;
}

// One DELTA/SNAPSHOT entry, byte by byte.
inline void put_entry(std::vector<std::uint8_t>& p, std::uint16_t id, std::uint8_t status, double value,
                      std::uint8_t flags = 0) {
  put_le(p, id, 2);
  p.push_back(status);
  p.push_back(flags);
  std::uint64_t bits;
  std::memcpy(&bits, &value, 8);
  put_le(p, bits, 8);
}

inline Hello subscriber_hello(std::uint64_t hash = catalog_hash()) {
  Hello h;
  h.role = Role::Subscriber;
  h.catalog_hash = hash;
  h.signal_count = static_cast<std::uint16_t>(catalog().size());
  h.heartbeat_period_ms = 100;
  h.name = "raw-test-client";
  return h;
}

class TempDir {
 public:
  TempDir() {
    char tmpl[] = "/tmp/meter-proto-test-XXXXXX";
    path_ = ::mkdtemp(tmpl);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  Endpoint unix_endpoint(const std::string& name = "link.sock") const {
    return Endpoint::parse("unix:" + file(name));
  }

 private:
  std::string path_;
};

// Collects the link's log lines (and keeps them off the test output).
class LogCapture {
 public:
  LogCapture() {
    set_log_sink([this](std::string_view line) {
      std::lock_guard lock(mutex_);
      lines_.emplace_back(line);
    });
  }
  ~LogCapture() { set_log_sink({}); }
  std::vector<std::string> lines() const {
    std::lock_guard lock(mutex_);
    return lines_;
  }
  bool contains(std::string_view needle) const {
    for (const auto& l : lines()) {
      if (l.find(needle) != std::string::npos) return true;
    }
    return false;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> lines_;
};

inline LinkOptions fast_options(std::string name = "") {
  LinkOptions o;
  // Short enough that loss tests finish fast, long enough (150 ms to loss) that a loaded 2-core CI
  // machine does not see spurious losses.
  o.heartbeat_period = std::chrono::milliseconds(50);
  o.reconnect_min = std::chrono::milliseconds(5);
  o.reconnect_max = std::chrono::milliseconds(40);
  o.name = std::move(name);
  return o;
}

// Writes a link key file with mode 0600 (the loader refuses anything wider): one line per key,
// the first the one that end tags with. Key bytes are `seed`, seed+1, ... so keys differ by seed.
inline std::string write_key_file(const std::string& path, const std::vector<std::pair<std::uint32_t, int>>& keys) {
  std::ofstream out(path, std::ios::trunc);
  for (const auto& [id, seed] : keys) {
    out << id << ' ';
    for (int i = 0; i < 32; ++i) {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02x", (seed + i) & 0xFF);
      out << hex;
    }
    out << '\n';
  }
  out.close();
  ::chmod(path.c_str(), 0600);
  return path;
}

// Drives both ends until `done()` or the limit; true if done.
template <typename Done>
bool pump(Publisher& pub, Subscriber& sub, Done done,
          std::chrono::milliseconds limit = std::chrono::milliseconds(3000)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    pub.poll(std::chrono::milliseconds(0));
    sub.poll(std::chrono::milliseconds(2));
    if (done()) return true;
  }
  return false;
}

// A bare SEQPACKET client that speaks raw bytes to a Publisher.
class RawUnixClient {
 public:
  explicit RawUnixClient(const std::string& path) {
    fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    const detail::UnixAddress addr(path);  // the product's address, any path length
    connected_ = addr.error() == 0 && ::connect(fd_, addr.get(), addr.size()) == 0;
  }
  ~RawUnixClient() { ::close(fd_); }
  bool connected() const { return connected_; }
  bool send(const std::vector<std::uint8_t>& bytes) {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // Receives one datagram, waiting up to timeout; empty on timeout/EOF.
  std::vector<std::uint8_t> receive(Publisher& pub, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::vector<std::uint8_t> buf(kMaxFrameSize);
    while (std::chrono::steady_clock::now() < deadline) {
      pub.poll(std::chrono::milliseconds(0));
      const ssize_t n = ::recv(fd_, buf.data(), buf.size(), MSG_DONTWAIT);
      if (n > 0) {
        buf.resize(static_cast<std::size_t>(n));
        return buf;
      }
      if (n == 0) {
        eof_ = true;
        return {};
      }
      ::usleep(1000);
    }
    return {};
  }
  bool eof() const { return eof_; }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  bool connected_ = false;
  bool eof_ = false;
};

}  // namespace meter::protocol::test
