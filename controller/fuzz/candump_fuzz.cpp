// Fuzzes the candump -L log reader the way meter-controller replays and decodes a log: parse the
// text, then hand every frame to the demo vehicle's model (DBC decode, mapping, conditioning) and
// decode it as `meter-controller decode` does. Every parsed frame must also survive the writer:
// formatting it and parsing the line again gives the same frame.
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "fixed_vehicle.hpp"
#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/model/model.hpp"

using namespace meter::controller;

namespace {
bool same_frame(const CanFrame& a, const CanFrame& b) {
  return a.id == b.id && a.extended == b.extended && a.rtr == b.rtr && a.error == b.error && a.fd == b.fd &&
         a.fd_flags == b.fd_flags && a.len == b.len && a.len8_dlc == b.len8_dlc &&
         std::memcmp(a.data.data(), b.data.data(), a.rtr ? 0 : a.len) == 0;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ParsedLog log = parse_candump_log(fuzz::as_text(data, size));
  if (log.frames.size() + log.bad_lines.size() > log.lines) std::abort();

  const Database& db = fuzz::demo_dbc();
  Model model(&db, fuzz::demo_mapping());
  std::vector<DecodedSignal> decoded;
  bool started = false;
  for (const CanFrame& f : log.frames) {
    if (f.len > (f.fd ? 64 : 8) && !f.rtr) std::abort();
    if (!started) model.start(f.timestamp_ns), started = true;
    model.on_frame(f);
    model.update(f.timestamp_ns);
    if (!f.error && !f.rtr)
      if (const DbcMessage* m = db.find(f.id, f.extended))
        decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), decoded);

    std::string why;
    const auto again = parse_candump_line(format_candump_line(f, "can0"), &why);
    if (!again || !same_frame(again->frame, f)) std::abort();
  }
  return 0;
}
