// Fuzzes the Vector ASC reader the way meter-controller replays and decodes a log (the demo
// vehicle's model and `decode`), then writes what it read with the ASC writer: read back, it must
// give the same frames.
#include "fixed_vehicle.hpp"
#include "log_writer_round_trip.hpp"
#include "meter/controller/input/asc_log.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ParsedLog log = parse_asc_log(fuzz::as_text(data, size));
  fuzz::drive_demo_vehicle(log);
  fuzz::expect_written_log_reads_back(log, asc_log_format());
  return 0;
}
