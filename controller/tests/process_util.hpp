// Starting meter-controller as a process in tests, and reading what it wrote.
#pragma once

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace meter::controller::testing {

// Runs args[0] with args, its stderr into stderr_file; returns the child's pid.
inline pid_t spawn(const std::vector<std::string>& args, const std::string& stderr_file) {
  pid_t pid = ::fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    FILE* e = std::freopen(stderr_file.c_str(), "w", stderr);
    (void)e;
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// The whole file, or empty when it cannot be read.
inline std::string slurp(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "r");
  if (!f) return "";
  std::string s;
  char b[4096];
  std::size_t n;
  while ((n = std::fread(b, 1, sizeof b, f)) > 0) s.append(b, n);
  std::fclose(f);
  return s;
}

// Calls each() (which should wait a little, e.g. a Subscriber poll) until the child exits or limit
// has passed; a child still running then is killed. Returns whether it exited by itself; status
// gets its wait status.
template <class Each>
bool watch_until_exit(pid_t pid, std::chrono::seconds limit, Each each, int& status) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    each();
    if (::waitpid(pid, &status, WNOHANG) == pid) return true;
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return false;
}

}  // namespace meter::controller::testing
