// The sockaddr_un of a Unix socket path of any length. sun_path holds 107 bytes, but a checkout,
// a build folder or a test's work folder can sit deeper than that. A path that fits goes in as it
// is; a longer one is reached through its folder: the folder is opened (O_PATH) and the address
// becomes /proc/self/fd/N/<file name>, which bind() and connect() resolve like any other path, so
// the socket file still appears at the path that was asked for. The folder stays open as long as
// this object lives, which must cover the bind() or connect().
#pragma once

#include <sys/socket.h>
#include <sys/un.h>

#include <string>

#include "transport/unique_fd.hpp"

namespace meter::protocol::detail {

class UnixAddress {
 public:
  explicit UnixAddress(const std::string& path);

  // 0 when the address is usable, else the errno of opening the folder of a long path
  // (ENOENT when the folder does not exist yet: for a connecting end, "nobody listens yet").
  int error() const { return error_; }
  const sockaddr* get() const { return reinterpret_cast<const sockaddr*>(&addr_); }
  socklen_t size() const { return sizeof addr_; }

 private:
  sockaddr_un addr_{};
  UniqueFd folder_;
  int error_ = 0;
};

}  // namespace meter::protocol::detail
