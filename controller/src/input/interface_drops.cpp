#include "meter/controller/input/interface_drops.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <limits>

namespace meter::controller {

std::optional<std::uint64_t> parse_interface_counter(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  if (text.empty()) return std::nullopt;
  std::uint64_t v = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (v > (std::numeric_limits<std::uint64_t>::max() - digit) / 10) return std::nullopt;
    v = v * 10 + digit;
  }
  return v;
}

InterfaceDrops::InterfaceDrops(const std::string& interface, const std::string& sysfs_net) {
  const std::string path = sysfs_net + "/" + interface + "/statistics/rx_dropped";
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) return;
  const auto start = read_counter();
  if (!start) {
    ::close(fd_);
    fd_ = -1;
    return;
  }
  baseline_ = *start;
}

InterfaceDrops::~InterfaceDrops() {
  if (fd_ >= 0) ::close(fd_);
}

std::optional<std::uint64_t> InterfaceDrops::read_counter() const {
  char buf[32];
  // A sysfs attribute is generated afresh by every read from offset 0.
  const ssize_t n = ::pread(fd_, buf, sizeof buf, 0);
  if (n <= 0 || n == static_cast<ssize_t>(sizeof buf)) return std::nullopt;
  return parse_interface_counter(std::string_view(buf, static_cast<std::size_t>(n)));
}

std::uint64_t InterfaceDrops::read() {
  if (fd_ < 0) return last_;
  const auto now = read_counter();
  // The counter only grows while the interface exists; a smaller value (the interface was
  // recreated under the same name) keeps the count reached so far.
  if (now && *now >= baseline_) last_ = std::max(last_, *now - baseline_);
  return last_;
}

}  // namespace meter::controller
