#include "meter/runner/process_signals.hpp"

#include <csignal>

namespace meter::runner {
namespace {

volatile std::sig_atomic_t g_stop = 0;
volatile std::sig_atomic_t g_dump_request = 0;

void on_stop(int) { g_stop = 1; }
void on_dump_request(int) { g_dump_request = 1; }

}  // namespace

void install_dump_request_handler() { std::signal(SIGUSR1, on_dump_request); }

void install_stop_handlers() {
  std::signal(SIGINT, on_stop);
  std::signal(SIGTERM, on_stop);
}

bool stop_requested() { return g_stop != 0; }

bool take_dump_request() {
  if (!g_dump_request) return false;
  g_dump_request = 0;
  return true;
}

}  // namespace meter::runner
