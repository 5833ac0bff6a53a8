// The Publisher's listening socket. Unix: a SOCK_SEQPACKET socket file of mode 0600 in a private
// (0700) folder, never stealing the path from a live publisher, replacing only a stale file, and
// removed again on destruction if it is still the file this object created. TCP: bound to the
// given host, with port 0 resolved to the ephemeral port the kernel chose.
#pragma once

#include <sys/stat.h>

#include <string>

#include "meter/protocol/endpoint.hpp"
#include "transport/unique_fd.hpp"

namespace meter::protocol::detail {

class ListeningSocket {
 public:
  // Binds and listens; throws std::runtime_error("publisher on <endpoint>: ...") with the reason.
  explicit ListeningSocket(Endpoint endpoint);
  ~ListeningSocket();
  ListeningSocket(const ListeningSocket&) = delete;
  ListeningSocket& operator=(const ListeningSocket&) = delete;

  int fd() const { return listener.get(); }
  const Endpoint& endpoint() const { return where; }  // TCP port 0 resolved

 private:
  [[noreturn]] void fail(const std::string& what, int err);
  void listen_unix();
  void listen_tcp();

  Endpoint where;
  UniqueFd listener;
  dev_t socket_dev = 0;  // identity of the socket file we created, so we only unlink our own
  ino_t socket_ino = 0;
};

}  // namespace meter::protocol::detail
