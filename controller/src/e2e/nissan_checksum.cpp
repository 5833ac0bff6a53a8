#include "meter/controller/e2e/nissan_checksum.hpp"

#include "meter/controller/e2e/chrysler_checksum.hpp"

namespace meter::controller {

// One CRC, two makes: kept apart so a configuration names the make it was written for.
std::uint8_t nissan_checksum(std::span<const std::uint8_t> payload) { return chrysler_checksum(payload); }

}  // namespace meter::controller
