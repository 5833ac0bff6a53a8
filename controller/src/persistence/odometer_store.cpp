#include "meter/controller/persistence/odometer_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
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
}  // namespace

OdometerStore::OdometerStore(std::string dir) : dir_(std::move(dir)), path_(dir_ + "/odometer.state") {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("state dir " + dir_ + ": " + ec.message());
}

std::string OdometerStore::format(const OdometerRecord& r) {
  std::string body = "meter-odometer 1\nodo_um " + std::to_string(r.odo_um) + "\ntrip_um " +
                     std::to_string(r.trip_um) + "\nseq " + std::to_string(r.sequence) + "\n";
  char crc[32];
  std::snprintf(crc, sizeof crc, "crc %08x\n", crc32(body));
  return body + crc;
}

std::optional<OdometerRecord> OdometerStore::parse(const std::string& text, std::string* why) {
  auto fail = [&](const std::string& w) -> std::optional<OdometerRecord> {
    if (why) *why = w;
    return std::nullopt;
  };
  auto crc_pos = text.rfind("crc ");
  if (crc_pos == std::string::npos) return fail("no 'crc' line (truncated file)");
  std::string body = text.substr(0, crc_pos);
  unsigned long want = std::strtoul(text.c_str() + crc_pos + 4, nullptr, 16);
  if (crc32(body) != want) return fail("CRC mismatch (damaged file)");
  std::istringstream in(body);
  std::string magic, key;
  int version = 0;
  in >> magic >> version;
  if (magic != "meter-odometer" || version != 1) return fail("expected 'meter-odometer 1' header");
  OdometerRecord r;
  if (!(in >> key >> r.odo_um) || key != "odo_um") return fail("expected 'odo_um <integer>'");
  if (!(in >> key >> r.trip_um) || key != "trip_um") return fail("expected 'trip_um <integer>'");
  if (!(in >> key >> r.sequence) || key != "seq") return fail("expected 'seq <integer>'");
  if (r.odo_um < 0 || r.trip_um < 0) return fail("negative distance");
  return r;
}

std::optional<OdometerRecord> OdometerStore::load() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string why;
  auto r = parse(ss.str(), &why);
  if (!r) throw std::runtime_error(path_ + ": " + why);
  return r;
}

void OdometerStore::save(const OdometerRecord& r) {
  const std::string text = format(r);
  const std::string tmp = path_ + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(tmp + ": " + std::strerror(errno));
  std::size_t off = 0;
  while (off < text.size()) {
    ssize_t n = ::write(fd, text.data() + off, text.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      int e = errno;
      ::close(fd);
      throw std::runtime_error(tmp + ": write: " + std::strerror(e));
    }
    off += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    int e = errno;
    ::close(fd);
    throw std::runtime_error(tmp + ": fsync: " + std::strerror(e));
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path_.c_str()) != 0) throw std::runtime_error(path_ + ": rename: " + std::strerror(errno));
  // The rename itself must reach the disk, or a crash could bring the old name back.
  int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace meter::controller
