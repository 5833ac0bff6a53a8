// A small vehicle for the mapping and model tests: a DBC with a 20 ms speed message (two wheel
// speeds, gear, turn lamp) and a 100 ms temperature message (float coolant, ranged outside), plus
// a frame builder.
#pragma once

#include <algorithm>
#include <cstdint>
#include <initializer_list>

#include "meter/controller/input/can_frame.hpp"

namespace meter::controller::testing {

inline const char* kDbc =
    "BO_ 256 Speed: 8 ECU\n"
    " SG_ WheelA : 0|16@1+ (0.01,0) [0|100] \"m/s\" ICL\n"
    " SG_ WheelB : 16|16@1+ (0.01,0) [0|100] \"m/s\" ICL\n"
    " SG_ Gear : 32|4@1+ (1,0) [0|6] \"\" ICL\n"
    " SG_ Left : 36|1@1+ (1,0) [0|1] \"\" ICL\n"
    "BO_ 512 Temps: 8 ECU\n"
    " SG_ Coolant : 0|32@1- (1,0) [0|0] \"C\" ICL\n"
    " SG_ Outside : 32|8@1+ (1,-40) [-40|80] \"C\" ICL\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 256 20;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 512 100;\n"
    "SIG_VALTYPE_ 512 Coolant : 1;\n";

inline constexpr std::int64_t ms = 1000000;

inline CanFrame frame(std::uint32_t id, std::int64_t t, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  f.timestamp_ns = t;
  f.len = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}

}  // namespace meter::controller::testing
