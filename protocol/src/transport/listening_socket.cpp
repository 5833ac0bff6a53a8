#include "transport/listening_socket.hpp"

#include "transport/unix_address.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <memory>
#include <stdexcept>

namespace meter::protocol::detail {

ListeningSocket::ListeningSocket(Endpoint endpoint) : where(std::move(endpoint)) {
  if (where.kind == Endpoint::Kind::Unix) {
    listen_unix();
  } else {
    listen_tcp();
  }
}

ListeningSocket::~ListeningSocket() {
  if (where.kind == Endpoint::Kind::Unix) {
    struct stat st{};
    if (::lstat(where.path.c_str(), &st) == 0 && st.st_dev == socket_dev && st.st_ino == socket_ino) {
      ::unlink(where.path.c_str());
    }
  }
}

void ListeningSocket::fail(const std::string& what, int err) {
  throw std::runtime_error("publisher on " + where.to_string() + ": " + what +
                           (err != 0 ? ": " + detail::errno_text(err) : std::string()));
}

void ListeningSocket::listen_unix() {
  // The parent folder: create it private (0700) if missing, as for /tmp/meter-<uid>/.
  const auto slash = where.path.rfind('/');
  if (slash != std::string::npos && slash > 0) {
    const std::string dir = where.path.substr(0, slash);
    struct stat st{};
    if (::stat(dir.c_str(), &st) != 0) {
      if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) fail("cannot create folder " + dir, errno);
    } else if (!S_ISDIR(st.st_mode)) {
      fail(dir + " exists and is not a folder", 0);
    }
  }
  const UnixAddress addr(where.path);
  if (addr.error() != 0) fail("cannot open the socket's folder", addr.error());

  struct stat st{};
  if (::lstat(where.path.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) fail(where.path + " exists and is not a socket; refusing to replace it", 0);
    // A live publisher answers; a stale file left by a crash refuses the connection.
    UniqueFd probe(::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0));
    if (probe && ::connect(probe.get(), addr.get(), addr.size()) == 0) {
      fail("another publisher is already listening there", 0);
    }
    ::unlink(where.path.c_str());
  }
  listener.reset(::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
  if (!listener) fail("socket(AF_UNIX, SOCK_SEQPACKET)", errno);
  // Bind with a private umask window would race other threads; the 0700 folder plus the chmod
  // right after bind plus SO_PEERCRED on every accept are the layers of protection.
  if (::bind(listener.get(), addr.get(), addr.size()) != 0) fail("bind", errno);
  if (::chmod(where.path.c_str(), 0600) != 0) fail("chmod 0600", errno);
  if (::lstat(where.path.c_str(), &st) == 0) {
    socket_dev = st.st_dev;
    socket_ino = st.st_ino;
  }
  if (::listen(listener.get(), 16) != 0) fail("listen", errno);
}

void ListeningSocket::listen_tcp() {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* res = nullptr;
  const std::string port = std::to_string(where.port);
  if (int rc = ::getaddrinfo(where.host.c_str(), port.c_str(), &hints, &res); rc != 0) {
    fail("cannot resolve host '" + where.host + "': " + ::gai_strerror(rc), 0);
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> guard(res, ::freeaddrinfo);
  int last_err = 0;
  for (auto* ai = res; ai != nullptr; ai = ai->ai_next) {
    UniqueFd fd(::socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, ai->ai_protocol));
    if (!fd) {
      last_err = errno;
      continue;
    }
    const int one = 1;
    ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd.get(), ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(fd.get(), 16) != 0) {
      last_err = errno;
      continue;
    }
    listener = std::move(fd);
    break;
  }
  if (!listener) fail("cannot bind/listen", last_err);
  sockaddr_storage ss{};
  socklen_t len = sizeof ss;
  ::getsockname(listener.get(), reinterpret_cast<sockaddr*>(&ss), &len);
  if (ss.ss_family == AF_INET) {
    where.port = ntohs(reinterpret_cast<sockaddr_in*>(&ss)->sin_port);
  } else if (ss.ss_family == AF_INET6) {
    where.port = ntohs(reinterpret_cast<sockaddr_in6*>(&ss)->sin6_port);
  }
}

}  // namespace meter::protocol::detail
