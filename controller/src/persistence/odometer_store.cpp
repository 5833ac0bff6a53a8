#include "meter/controller/persistence/odometer_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace meter::controller {

namespace {

std::uint32_t crc32(const std::string& s) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

constexpr std::size_t kMaxRecordBytes = 4096;  // a record is ~100 bytes: anything bigger is not one

std::runtime_error io_error(const std::string& file, const char* what, int err) {
  return std::runtime_error(file + ": " + what + ": " + std::strerror(err));
}

}  // namespace

OdometerStore::OdometerStore(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) dir_error_ = "cannot create the state directory: " + ec.message();
}

std::string OdometerStore::copy_path(int copy) const { return dir_ + (copy == 0 ? "/odometer.a" : "/odometer.b"); }

std::string OdometerStore::format(const OdometerRecord& r) {
  std::string body = "meter-odometer 2\nodo_um " + std::to_string(r.odo_um) + "\ntrip_um " + std::to_string(r.trip_um) +
                     "\nseq " + std::to_string(r.sequence) + "\npeer " + std::to_string(r.peer) + "\n";
  char crc[32];
  std::snprintf(crc, sizeof crc, "crc %08x\n", crc32(body));
  return body + crc;
}

std::optional<OdometerRecord> OdometerStore::parse(const std::string& text, std::string* why) {
  auto fail = [&](const std::string& w) -> std::optional<OdometerRecord> {
    if (why) *why = w;
    return std::nullopt;
  };
  if (text.empty()) return fail("empty file (zero length)");
  const auto crc_pos = text.rfind("crc ");
  if (crc_pos == std::string::npos || (crc_pos > 0 && text[crc_pos - 1] != '\n'))
    return fail("no 'crc' line (truncated file)");
  std::string crc_text = text.substr(crc_pos + 4);
  if (!crc_text.empty() && crc_text.back() == '\n') crc_text.pop_back();
  if (crc_text.size() != 8 || crc_text.find_first_not_of("0123456789abcdef") != std::string::npos)
    return fail("expected 'crc' and 8 hex digits on the last line (truncated or damaged file)");
  const std::string body = text.substr(0, crc_pos);
  if (crc32(body) != std::stoul(crc_text, nullptr, 16)) return fail("CRC mismatch (damaged file)");
  std::istringstream in(body);
  std::string magic, key;
  int version = 0;
  in >> magic >> version;
  if (magic != "meter-odometer" || (version != 1 && version != 2)) return fail("expected a 'meter-odometer 1' or '2' header");
  OdometerRecord r;
  if (!(in >> key >> r.odo_um) || key != "odo_um") return fail("expected 'odo_um <integer>'");
  if (!(in >> key >> r.trip_um) || key != "trip_um") return fail("expected 'trip_um <integer>'");
  if (!(in >> key >> r.sequence) || key != "seq") return fail("expected 'seq <integer>'");
  if (version == 2 && (!(in >> key >> r.peer) || key != "peer")) return fail("expected 'peer <integer>'");
  if (in >> key) return fail("unexpected '" + key + "' after the record");
  if (r.odo_um < 0 || r.trip_um < 0) return fail("negative distance");
  // No save can follow the largest sequence (it would wrap to 0 and lose to this copy): only a
  // damaged or hand-made file holds it.
  if (r.sequence == UINT64_MAX) return fail("sequence is the largest possible (a damaged or hand-made file)");
  return r;
}

OdometerStore::Copy OdometerStore::read_copy(const std::string& path) const {
  Copy c;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    c.exists = errno != ENOENT;
    c.why = std::string("cannot open: ") + std::strerror(errno);
    return c;
  }
  c.exists = true;
  std::string text;
  char buf[1024];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      c.why = std::string("read: ") + std::strerror(errno);
      ::close(fd);
      return c;
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > kMaxRecordBytes) {
      c.why = "larger than an odometer record (" + std::to_string(kMaxRecordBytes) + " bytes at most)";
      ::close(fd);
      return c;
    }
  }
  ::close(fd);
  c.record = parse(text, &c.why);
  return c;
}

OdometerLoad OdometerStore::load() {
  OdometerLoad out;
  refused_ = false;
  seq_ = 0;
  next_ = 0;
  if (!dir_error_.empty()) out.faults.push_back(dir_ + ": " + dir_error_);
  const Copy c[2] = {read_copy(copy_path(0)), read_copy(copy_path(1))};
  for (int i = 0; i < 2; ++i) {
    on_disk_[i] = c[i].record ? c[i].record->sequence : 0;
    if (c[i].exists && !c[i].record) out.faults.push_back(copy_path(i) + ": " + c[i].why);
  }
  auto refuse = [&](const std::string& why) {
    out.faults.push_back(why + "; the odometer is invalid and not written until 'meter-controller odometer-reset --state-dir " +
                         dir_ + "'");
    out.state = OdometerState::Refused;
    refused_ = true;
    return out;
  };
  if (!c[0].exists && !c[1].exists) {  // nothing in the two-copy layout: the old single file, or nothing
    const Copy legacy = read_copy(legacy_path());
    if (!legacy.exists) return out;
    if (!legacy.record) {
      out.faults.push_back(legacy_path() + ": " + legacy.why);
      return refuse(dir_ + ": no valid odometer record");
    }
    out.state = OdometerState::Restored;
    out.record = legacy.record;
    seq_ = legacy.record->sequence;
    return out;
  }
  if (!c[0].record && !c[1].record) return refuse(dir_ + ": no valid odometer copy");
  if (c[0].record && c[1].record) {
    const int n = c[1].record->sequence > c[0].record->sequence ? 1 : 0;
    const OdometerRecord &newest = *c[n].record, &other = *c[1 - n].record;
    if (newest.peer != 0 && other.sequence != newest.peer)
      return refuse(copy_path(1 - n) + ": holds sequence " + std::to_string(other.sequence) + " but " + copy_path(n) +
                    " was written when it held " + std::to_string(newest.peer) + " (a copy put back from an older state)");
    if (newest.odo_um < other.odo_um)
      return refuse(copy_path(n) + ": the newer copy holds less distance than " + copy_path(1 - n) +
                    " (the odometer must never go backwards)");
    out.record = newest;
    next_ = 1 - n;
  } else {
    const int v = c[0].record ? 0 : 1;
    out.record = c[v].record;
    next_ = 1 - v;
  }
  out.state = OdometerState::Restored;
  seq_ = out.record->sequence;
  return out;
}

void OdometerStore::write_copy(int copy, const OdometerRecord& r) {
  const std::string path = copy_path(copy), tmp = path + ".tmp", text = format(r);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error(tmp, "open", errno);
  auto fail = [&](const char* what) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmp.c_str());  // a full disk must not keep a half-written temp file
    return io_error(tmp, what, e);
  };
  std::size_t off = 0;
  while (off < text.size()) {
    const ssize_t n = ::write(fd, text.data() + off, text.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      throw fail("write");
    }
    off += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) throw fail("fsync");
  if (::close(fd) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    throw io_error(tmp, "close", e);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    throw io_error(path, "rename", e);
  }
  // The rename itself must reach the disk, or a crash could bring the old copy back (the other copy
  // still holds the previous record, so even then nothing older than one interval returns).
  const int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

std::uint64_t OdometerStore::save(std::int64_t odo_um, std::int64_t trip_um) {
  if (refused_)
    throw std::runtime_error(dir_ + ": the odometer state is refused; 'meter-controller odometer-reset' first");
  const OdometerRecord r{odo_um, trip_um, seq_ + 1, on_disk_[1 - next_]};
  write_copy(next_, r);
  on_disk_[next_] = r.sequence;
  seq_ = r.sequence;
  next_ = 1 - next_;
  if (on_disk_[0] != 0 && on_disk_[1] != 0) ::unlink(legacy_path().c_str());  // migrated: both copies hold records
  return r.sequence;
}

std::optional<OdometerRecord> OdometerStore::best_valid() const {
  std::optional<OdometerRecord> best;
  for (const std::string& p : {copy_path(0), copy_path(1), legacy_path()})
    if (const Copy c = read_copy(p); c.record && (!best || c.record->odo_um > best->odo_um)) best = c.record;
  return best;
}

void OdometerStore::reset(std::int64_t odo_um, std::int64_t trip_um) {
  if (!dir_error_.empty()) throw std::runtime_error(dir_ + ": " + dir_error_);
  std::uint64_t base = seq_;
  for (const std::string& p : {copy_path(0), copy_path(1), legacy_path()})
    if (const Copy c = read_copy(p); c.record) base = std::max(base, c.record->sequence);
  write_copy(0, {odo_um, trip_um, base + 1, 0});
  write_copy(1, {odo_um, trip_um, base + 2, base + 1});
  ::unlink(legacy_path().c_str());
  on_disk_[0] = base + 1;
  on_disk_[1] = base + 2;
  seq_ = base + 2;
  next_ = 0;
  refused_ = false;
}

}  // namespace meter::controller
