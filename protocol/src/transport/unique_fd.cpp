#include "transport/unique_fd.hpp"

#include <unistd.h>

#include <cstring>

namespace meter::protocol::detail {

void UniqueFd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

std::string errno_text(int err) { return std::strerror(err); }
}  // namespace meter::protocol::detail
