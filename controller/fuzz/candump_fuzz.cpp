// Fuzzes the candump -L log reader the way meter-controller replays and decodes a log: parse the
// text, then hand every frame to the demo vehicle's model (DBC decode, mapping, conditioning) and
// decode it as `meter-controller decode` does. Every parsed frame must also survive the writer:
// formatting it and parsing the line again gives the same frame.
#include <cstdlib>
#include <string>

#include "fixed_vehicle.hpp"
#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/candump_log.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ParsedLog log = parse_candump_log(fuzz::as_text(data, size));
  fuzz::drive_demo_vehicle(log);
  for (const CanFrame& f : log.frames) {
    std::string why;
    const auto again = parse_candump_line(format_candump_line(f, "can0"), &why);
    if (!again) std::abort();
    CanFrame back = again->frame;
    back.channel = f.channel;  // the line's interface is not the log's channel numbering
    if (!fuzz::same_logged_frame(back, f, true)) std::abort();
  }
  return 0;
}
