// Vector BLF logs (the binary format of CANoe / CANalyzer), read object by object from a stream:
// the file header (its start time, a local wall time), then objects; log containers are inflated
// one at a time (zlib), so a file of any size is never held whole in memory. CAN_MESSAGE,
// CAN_MESSAGE2, CAN_FD_MESSAGE, CAN_FD_MESSAGE_64 and CAN_ERROR_EXT objects become frames; objects of
// other kinds are passed over and counted. A truncated file, a corrupt zlib block or a broken object
// ends the reading with a bad record naming the byte offset and the object; the frames before it
// are kept.
#pragma once

#include <cstdint>
#include <istream>
#include <memory>
#include <string_view>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The BLF object types this reader knows (Vector's numbers).
inline constexpr std::uint32_t kBlfCanMessage = 1, kBlfLogContainer = 10, kBlfCanErrorExt = 73, kBlfCanMessage2 = 86,
                               kBlfCanFdMessage = 100, kBlfCanFdMessage64 = 101;
inline constexpr std::size_t kBlfFileHeaderSize = 144;

// A BLF file a frame at a time, as run, decode and convert-log read it: one container inflated at a
// time, its objects read one per frame asked. The bad records' numbers are object numbers (1-based,
// in file order, a container's objects after the container).
std::unique_ptr<LogSource> open_blf_log(std::istream& in);
// The whole file in memory (tests, fuzzers, benches).
ParsedLog read_blf_log(std::istream& in);

// True when the head starts with the BLF signature "LOGG".
bool sniff_blf_log(std::string_view head);

// blf: recognised by its signature, else by .blf.
const LogFormat& blf_log_format();

}  // namespace meter::controller
