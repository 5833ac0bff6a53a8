// Starting meter-controller as a process in tests, and reading what it wrote.
#pragma once

#include <sys/types.h>
#include <unistd.h>

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
}  // namespace meter::controller::testing
