// Child processes for integration tests: start an executable with arguments, capture its output to
// a file, wait with a deadline, and never leave it running when the test ends.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace meter::testing {

class ChildProcess {
 public:
  // Starts argv[0] (a path) with the remaining arguments; stdout and stderr go to log_path.
  // Throws std::runtime_error if the process cannot be started.
  ChildProcess(std::vector<std::string> argv, std::string log_path);
  ~ChildProcess();  // SIGKILL + reap if still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Exit status (0..255, or 128+signal) once the process ended within the timeout; nullopt otherwise.
  std::optional<int> wait_for(std::chrono::milliseconds timeout);
  void signal(int sig);
  bool running();
  pid_t pid() const { return pid_; }
  const std::string& log_path() const { return log_path_; }
  std::string log() const;  // the captured output so far, for failure messages

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
  std::string log_path_;
};

// Path of a built executable: <build>/bin/<name>.
std::string built_executable(const std::string& name);

}  // namespace meter::testing
