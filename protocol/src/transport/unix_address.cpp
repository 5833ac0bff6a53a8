#include "transport/unix_address.hpp"

#include <fcntl.h>

#include <cerrno>
#include <cstring>

#include "meter/protocol/endpoint.hpp"

namespace meter::protocol::detail {

UnixAddress::UnixAddress(const std::string& path) {
  addr_.sun_family = AF_UNIX;
  if (path.size() < sizeof addr_.sun_path) {
    std::memcpy(addr_.sun_path, path.c_str(), path.size() + 1);
    return;
  }
  // Endpoint::parse has checked that the file name fits beside the /proc/self/fd/N/ prefix.
  const auto slash = path.rfind('/');
  const std::string folder = slash == 0 ? "/" : path.substr(0, slash);
  const std::string name = path.substr(slash + 1);
  folder_.reset(::open(folder.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC));
  if (!folder_) {
    error_ = errno;
    return;
  }
  const std::string via = "/proc/self/fd/" + std::to_string(folder_.get()) + "/" + name;
  if (via.size() >= sizeof addr_.sun_path) {  // only with an fd number beyond what the check allowed
    error_ = ENAMETOOLONG;
    return;
  }
  std::memcpy(addr_.sun_path, via.c_str(), via.size() + 1);
}

}  // namespace meter::protocol::detail
