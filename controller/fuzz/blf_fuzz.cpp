// Fuzzes the Vector BLF reader (object framing, zlib log containers, objects across containers)
// the way meter-controller replays and decodes a log (the demo vehicle's model and `decode`), then
// writes what it read with the BLF writer: read back, it must give the same frames.
#include <sstream>
#include <string>

#include "fixed_vehicle.hpp"
#include "log_writer_round_trip.hpp"
#include "meter/controller/input/blf_log.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(fuzz::as_text(data, size)));
  const ParsedLog log = read_blf_log(in);
  fuzz::drive_demo_vehicle(log);
  fuzz::expect_written_log_reads_back(log, blf_log_format());
  return 0;
}
