// Fuzzes the PCAN TRC reader (every file version, $COLUMNS) the way meter-controller replays and
// decodes a log: every frame into the demo vehicle's model and decoded as `decode` does.
#include "fixed_vehicle.hpp"
#include "meter/controller/input/trc_log.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::drive_demo_vehicle(parse_trc_log(fuzz::as_text(data, size)));
  return 0;
}
