// The independent Modbus TCP peer (pymodbus_server.py, python3-pymodbus) on a free loopback port.
// It serves the registers that script lists; stopped (SIGTERM) when the object goes.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace meter::controller::testing {

class PymodbusPeer {
 public:
  PymodbusPeer() {
    // A free port: bind to 0, read it back, release it for the Python server.
    int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
      socklen_t len = sizeof a;
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
      port_ = ntohs(a.sin_port);
    }
    ::close(s);
    if (port_ == 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      std::string script = std::string(METER_SOURCE_DIR) + "/controller/tests/pymodbus_server.py";
      std::string p = std::to_string(port_);
      ::execl("/usr/bin/python3", "python3", script.c_str(), p.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~PymodbusPeer() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    int status;
    ::waitpid(pid_, &status, 0);
  }
  PymodbusPeer(const PymodbusPeer&) = delete;
  PymodbusPeer& operator=(const PymodbusPeer&) = delete;
  bool started() const { return pid_ > 0; }
  int port() const { return port_; }

 private:
  int port_ = 0;
  pid_t pid_ = -1;
};

}  // namespace meter::controller::testing
