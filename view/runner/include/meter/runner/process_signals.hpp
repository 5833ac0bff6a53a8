// The live view's POSIX signals: SIGINT/SIGTERM end the loop after the current frame; SIGUSR1
// asks for the next frame to be dumped (kill -USR1 <pid>).
#pragma once

namespace meter::runner {

// Install before the slow start-up (package, GL context): a dump request must never meet
// SIGUSR1's default action, which would end the process.
void install_dump_request_handler();
void install_stop_handlers();

bool stop_requested();
// True once per request received since the previous call.
bool take_dump_request();

}  // namespace meter::runner
