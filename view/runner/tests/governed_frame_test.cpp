// The frame-rate governor's runner side without GL: the test-only cost injection's option text,
// the cost file's default place, and the governor's columns in frames.csv and the timing CSV
// (present only when the governor is on).
#include "meter/runner/governed_frame.hpp"
#include "meter/runner/timing_csv.hpp"

#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

TEST(CostInjection, ReadsNanosecondsPerPixelAndAFrameRange) {
  const CostInjection c = parse_cost_injection("2.5@20-80");
  EXPECT_DOUBLE_EQ(c.ns_per_pixel, 2.5);
  EXPECT_EQ(c.first, 20u);
  EXPECT_EQ(c.last, 80u);
  EXPECT_EQ(parse_cost_injection("1@7-7").last, 7u);
}

TEST(CostInjection, EveryMalformedTextIsNamed) {
  for (const char* bad : {"", "50", "50@", "50@3", "50@3-", "@1-2", "x@1-2", "50x@1-2", "0@1-2", "-5@1-2", "nan@1-2",
                          "inf@1-2", "50@2-1", "50@a-2", "50@1-2x", "50@-1-2"}) {
    try {
      parse_cost_injection(bad);
      ADD_FAILURE() << "\"" << bad << "\" was accepted";
    } catch (const ViewError& e) {
      EXPECT_EQ(std::string(e.what()),
                std::string("--inject-cost: expected NS_PER_PIXEL@FIRST-LAST (e.g. 50@20-80), got \"") + bad + "\"");
    }
  }
}

TEST(GovernedFrame, TheCostFileSitsBesideThePackage) {
  EXPECT_EQ(default_costs_path("out/cluster.msp"), "out/cluster.msp.costs.json");
}

TEST(GovernedFrame, GovernorColumnsOnlyWhenTheGovernorIsOn) {
  const auto dir = testing::scratch_dir();
  engine::FrameTiming t;
  t.update_ms = 0.5, t.submit_ms = 1.25, t.gpu_readback_ms = 2, t.drawn = true;
  const GovernorCells cells{9.5, 10.25, 2, 1, 0.75f, "needle=gouraud/lod1 dial=pbr/lod2"};
  {
    TimingCsv off((dir / "off.csv").string());
    off.row(0, 0.0, t, &cells);  // cells given but no columns: the file is as without a governor
    TimingCsv on((dir / "on.csv").string(), true);
    on.row(0, 0.0, t, &cells);
    on.row(1, 0.5, t);  // no cells yet: zeros
    FramesCsv frames(dir / "frames.csv", {}, false, true);
    frames.row(3, 0.1, "frame_000003.png", true, true, {}, nullptr, &cells);
  }
  EXPECT_EQ(testing::read_lines(dir / "off.csv"),
            (std::vector<std::string>{"frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn", "0,0.0000,0.5000,1.2500,2.0000,1"}));
  EXPECT_EQ(testing::read_lines(dir / "on.csv"),
            (std::vector<std::string>{
                "frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn,predicted_ms,measured_ms,units_reduced,msaa,scale,reduced",
                "0,0.0000,0.5000,1.2500,2.0000,1,9.500,10.250,2,1,0.7500,\"needle=gouraud/lod1 dial=pbr/lod2\"",
                "1,0.5000,0.5000,1.2500,2.0000,1,0.000,0.000,0,0,1.0000,\"\""}));
  EXPECT_EQ(testing::read_lines(dir / "frames.csv"),
            (std::vector<std::string>{"frame,time_s,png,link_up,drawn,predicted_ms,measured_ms,units_reduced,msaa,scale,reduced",
                                      "3,0.1000,frame_000003.png,1,1,9.500,10.250,2,1,0.7500,\"needle=gouraud/lod1 dial=pbr/lod2\""}));
}

}  // namespace
}  // namespace meter::runner
