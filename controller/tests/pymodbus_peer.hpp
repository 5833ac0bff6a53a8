// The independent Modbus peers (python3-pymodbus) the Modbus client tests talk to, each a child
// process stopped (SIGTERM) when the object goes:
// - PymodbusPeer: pymodbus_server.py, Modbus TCP on a free loopback port;
// - PymodbusRtuPeer: pymodbus_rtu_server.py, Modbus RTU over a socat pseudo-terminal pair in a
//   fresh temporary folder (the units it serves, a silent one and one answering with bad CRCs are
//   listed in that script), and Modbus TCP on a free loopback port from the same process.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace meter::controller::testing {

// A free loopback TCP port: bind to 0, read it back, release it for the Python server.
inline int free_loopback_port() {
  int port = 0;
  int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
    socklen_t len = sizeof a;
    ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
  }
  ::close(s);
  return port;
}

// controller/tests/SCRIPT run by /usr/bin/python3 (where the Debian python3-pymodbus lives) with ARGS.
class PythonChild {
 public:
  PythonChild(const std::string& script, const std::vector<std::string>& args) {
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string path = std::string(METER_SOURCE_DIR) + "/controller/tests/" + script;
      std::vector<char*> argv{const_cast<char*>("python3"), const_cast<char*>(path.c_str())};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv("/usr/bin/python3", argv.data());
      ::_exit(127);
    }
  }
  ~PythonChild() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    int status;
    ::waitpid(pid_, &status, 0);
  }
  PythonChild(const PythonChild&) = delete;
  PythonChild& operator=(const PythonChild&) = delete;
  bool started() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

class PymodbusPeer {
 public:
  PymodbusPeer() : port_(free_loopback_port()), child_("pymodbus_server.py", {std::to_string(port_)}) {}
  bool started() const { return port_ != 0 && child_.started(); }
  int port() const { return port_; }

 private:
  int port_;
  PythonChild child_;
};

class PymodbusRtuPeer {
 public:
  PymodbusRtuPeer()
      : dir_(make_dir()), port_(free_loopback_port()), child_("pymodbus_rtu_server.py", {dir_, std::to_string(port_)}) {}
  ~PymodbusRtuPeer() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  bool started() const { return !dir_.empty() && port_ != 0 && child_.started(); }
  std::string client_device() const { return dir_ + "/client"; }  // the master's end of the pair
  int tcp_port() const { return port_; }

 private:
  static std::string make_dir() {
    std::string t = (std::filesystem::temp_directory_path() / "meter-rtu-XXXXXX").string();
    return ::mkdtemp(t.data()) ? t : std::string();
  }
  std::string dir_;
  int port_;
  PythonChild child_;
};

}  // namespace meter::controller::testing
