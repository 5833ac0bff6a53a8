// Frames a network interface dropped before any socket saw them. When the kernel's input backlog
// (net.core.netdev_max_backlog) has no room for a received frame, it drops the frame and counts it
// in the interface's rx_dropped; no socket's SO_RXQ_OVFL sees that loss, and every socket on the
// interface loses the frame alike.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace meter::controller {

// A sysfs counter's text ("1234\n") as a number; nullopt for anything else (empty, a sign, other
// characters, more than 64 bits).
std::optional<std::uint64_t> parse_interface_counter(std::string_view text);

// <sysfs_net>/<interface>/statistics/rx_dropped, counted from construction on. An interface
// without that file counts nothing (available() is false); a read that fails or returns text that
// is not a counter keeps the last count.
class InterfaceDrops {
 public:
  explicit InterfaceDrops(const std::string& interface, const std::string& sysfs_net = "/sys/class/net");
  ~InterfaceDrops();
  InterfaceDrops(const InterfaceDrops&) = delete;
  InterfaceDrops& operator=(const InterfaceDrops&) = delete;

  bool available() const { return fd_ >= 0; }
  // Reads the counter again: the interface's drops since construction.
  std::uint64_t read();

 private:
  std::optional<std::uint64_t> read_counter() const;
  int fd_ = -1;
  std::uint64_t baseline_ = 0;
  std::uint64_t last_ = 0;
};

}  // namespace meter::controller
