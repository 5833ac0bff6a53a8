// decode --e2e on a real vehicle's log: the Toyota 86 (a Subaru pre-global platform car) log with
// opendbc's Subaru pre-global DBC passes every check; the same log under a checksum rule that adds
// the id's bytes (as the sister global platform's sum does) is reported as a likely configuration
// mismatch naming the message; a DBC without checksum or counter signals says there is nothing to
// check.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "meter/controller/run/decode_e2e_command.hpp"

namespace {
const std::string kCan = std::string(METER_SHARED_DIR) + "/data/can";
const std::string kLog = kCan + "/ft86_motec/can_sample.log";
const std::string kSubaruDbc = kCan + "/opendbc/subaru_outback_2015_generated.dbc";

TEST(DecodeE2e, ARealLogWithItsFittingDbcPassesEveryCheck) {
  std::ostringstream out, err;
  ASSERT_EQ(meter::controller::decode_e2e_command(kSubaruDbc, kLog, "", out, err), 0) << err.str();
  const std::string e = err.str();
  EXPECT_NE(e.find("make Subaru (pre-global platform) (from the file name): checksum algorithm subaru-preglobal"), std::string::npos) << e;
  EXPECT_NE(e.find("Steering (0x2): subaru-preglobal checksum in Checksum, counter COUNTER (3 bits)"), std::string::npos) << e;
  EXPECT_NE(e.find("e2e summary: 30397 frames checked, 0 refused"), std::string::npos) << e;
  EXPECT_NE(e.find("Steering (0x2, subaru-preglobal): 9028 checked, 0 refused"), std::string::npos) << e;
  std::istringstream rows(out.str());
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "timestamp,message,checksum,received,expected,counter,counter_status,used");
  std::size_t n = 0, used = 0;
  while (std::getline(rows, line)) ++n, used += line.ends_with(",yes");
  EXPECT_EQ(n, 30397u);
  EXPECT_EQ(used, n);
}

TEST(DecodeE2e, AWrongChecksumRuleIsReportedAsAMismatchNamingTheMessage) {
  const auto dir = std::filesystem::temp_directory_path() / ("meter-e2e-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string map = (dir / "wrong.map").string();
  std::ofstream(map) << "[e2e Steering]\nchecksum = tesla\n";
  std::ostringstream out, err;
  EXPECT_EQ(meter::controller::decode_e2e_command(kSubaruDbc, kLog, map, out, err), 2) << err.str();
  const std::string e = err.str();
  EXPECT_NE(e.find("e2e: likely configuration mismatch: Steering (0x2) refused 9028 of 9028 frames (checksum tesla does not fit"),
            std::string::npos) << e;
  EXPECT_NE(e.find("configured by map file " + map + ":1"), std::string::npos) << e;
  std::filesystem::remove_all(dir);
}

TEST(DecodeE2e, ADbcWithoutConventionsSaysThereIsNothingToCheck) {
  std::ostringstream out, err;
  EXPECT_EQ(meter::controller::decode_e2e_command(kCan + "/ft86_motec/sample_can_spec.dbc", kLog, "", out, err), 0);
  EXPECT_NE(err.str().find("the file name names no make known here"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("no message has a checksum or counter signal: nothing to check"), std::string::npos) << err.str();
}

}  // namespace
