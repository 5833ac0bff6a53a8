// Fuzzes the PCAN TRC reader (every file version, $COLUMNS) the way meter-controller replays and
// decodes a log: every frame into the demo vehicle's model and decoded as `decode` does.
#include <sstream>
#include <string>

#include "fixed_vehicle.hpp"
#include "meter/controller/input/trc_log.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(fuzz::as_text(data, size)));
  fuzz::drive_demo_vehicle(read_trc_log(in));
  return 0;
}
