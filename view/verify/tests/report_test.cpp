#include <gtest/gtest.h>

#include "meter/verify/verify.hpp"

using namespace meter;
using namespace meter::verify;

namespace {

VerifyReport two_frames() {
  VerifyReport r;
  r.package = "cluster.msp", r.run_dir = "run<1>", r.frames = 2;
  CheckResult ok;
  ok.frame = 0, ok.png = "frame_000000.png", ok.region = "TT_ABS", ok.kind = bridge::SafetyKind::Telltale;
  ok.checked = true, ok.verdict = {true, "lit", "lit (on)", 0.5};
  CheckResult bad = ok;
  bad.frame = 30, bad.png = "frame_000030.png", bad.region = "Speedo_Needle", bad.kind = bridge::SafetyKind::Needle;
  bad.verdict = {false, "60.00 at -64.6 deg", "-61.6 deg & \"x\"", 3.0};
  CheckResult skipped = ok;
  skipped.checked = false, skipped.region = "Text_Gear", skipped.kind = bridge::SafetyKind::Readout;
  r.checks = {ok, bad, skipped};
  return r;
}

}  // namespace

TEST(VerifyReport, JunitHasOneCasePerFrameAndRegionWithTheFailureNamed) {
  const std::string x = junit_xml(two_frames());
  EXPECT_NE(x.find("<testsuites name=\"meter-verify\" tests=\"3\" failures=\"1\">"), std::string::npos) << x;
  EXPECT_NE(x.find("testsuite name=\"run&lt;1&gt;\""), std::string::npos);
  EXPECT_NE(x.find("<testcase classname=\"frame_000000.png\" name=\"telltale TT_ABS\" time=\"0\"/>"), std::string::npos);
  EXPECT_NE(x.find("<failure message=\"frame 30 (frame_000030.png), needle Speedo_Needle: expected 60.00 at -64.6 deg, "
                   "seen -61.6 deg &amp; &quot;x&quot;, difference 3.000\""),
            std::string::npos)
      << x;
  EXPECT_NE(x.find("name=\"readout Text_Gear\" time=\"0\"><skipped"), std::string::npos);
  EXPECT_EQ(two_frames().failures(), 1u);
}

TEST(VerifyReport, SummaryCountsPerRegionAndListsFailures) {
  const std::string s = summary_table(two_frames());
  EXPECT_NE(s.find("2 frames, 3 checks, 1 failed"), std::string::npos) << s;
  EXPECT_NE(s.find("FAIL frame 30 (frame_000030.png), needle Speedo_Needle"), std::string::npos) << s;
}
