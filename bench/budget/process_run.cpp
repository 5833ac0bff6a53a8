#include "process_run.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>

namespace meter::bench {

ProcessRun run_process(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                       const std::string& png, bool quiet) {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); };
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto t0 = Clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    for (const auto& e : env) {
      const auto eq = e.find('=');
      if (eq == std::string::npos) unsetenv(e.c_str());
      else setenv(e.substr(0, eq).c_str(), e.substr(eq + 1).c_str(), 1);
    }
    if (quiet) {  // the tool's report is not the bench's
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO);
    }
    execv(args[0], args.data());
    _exit(127);
  }
  ProcessRun r;
  int status = 0;
  struct rusage ru {};
  while (wait4(pid, &status, WNOHANG, &ru) == 0) {
    if (r.to_png_ms < 0 && !png.empty() && std::filesystem::exists(png)) r.to_png_ms = ms(t0);
    usleep(1000);
  }
  r.to_exit_ms = ms(t0);
  if (r.to_png_ms < 0 && std::filesystem::exists(png)) r.to_png_ms = r.to_exit_ms;
  r.peak_kib = ru.ru_maxrss;
  r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && (png.empty() || r.to_png_ms >= 0);
  return r;
}

}  // namespace meter::bench
