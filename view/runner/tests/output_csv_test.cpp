// frames.csv (values as drawn, per-signal and per-text columns) and the timing CSV.
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/timing_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using protocol::SignalStatus;

engine::Binding binding(engine::BindingKind kind, const std::string& signal, const std::string& node = "") {
  engine::Binding b;
  b.kind = kind;
  b.signal = signal;
  b.node = node;
  return b;
}

engine::BindingState state(double value, SignalStatus status, bool failsafe, const std::string& text = "") {
  engine::BindingState s;
  s.value = value;
  s.status = status;
  s.failsafe = failsafe;
  s.text = text;
  return s;
}

TEST(FramesCsv, OneColumnGroupPerSignalAndOneColumnPerText) {
  const auto dir = testing::scratch_dir();
  using K = engine::BindingKind;
  // A needle and a readout of the same speed, a telltale, a gear readout.
  const std::vector<engine::Binding> bindings = {
      binding(K::Animation, "Vehicle.Speed"), binding(K::Text, "Vehicle.Speed", "speed_text"),
      binding(K::Visibility, "Cluster.Telltale.ABS", "abs"),
      binding(K::Text, "Vehicle.Powertrain.Transmission.CurrentGear", "gear")};
  {
    FramesCsv csv(dir / "frames.csv", bindings);
    csv.row(0, 0.0, "frame_000000.png", true, true,
            {state(12.345678901, SignalStatus::Valid, false), state(13, SignalStatus::Valid, false, "13"),
             state(1, SignalStatus::TimedOut, true), state(126, SignalStatus::Valid, false, "P")});
    csv.row(30, 1.00004, "frame_000030.png", false, false,
            {state(0, SignalStatus::NotAvailable, true), state(0, SignalStatus::NotAvailable, true, "say \"hi\", ok"),
             state(0, SignalStatus::Invalid, true), state(0, SignalStatus::NotAvailable, true, "")});
  }
  EXPECT_EQ(testing::read_lines(dir / "frames.csv"),
            (std::vector<std::string>{
                "frame,time_s,png,link_up,drawn,Vehicle.Speed,Vehicle.Speed.status,Vehicle.Speed.failsafe,"
                "Cluster.Telltale.ABS,Cluster.Telltale.ABS.status,Cluster.Telltale.ABS.failsafe,"
                "Vehicle.Powertrain.Transmission.CurrentGear,Vehicle.Powertrain.Transmission.CurrentGear.status,"
                "Vehicle.Powertrain.Transmission.CurrentGear.failsafe,speed_text.text,gear.text,speed_text.value,gear.value",
                "0,0.0000,frame_000000.png,1,1,12.345679,valid,0,1.000000,timed-out,1,126.000000,valid,0,\"13\",\"P\",13.000000,126.000000",
                "30,1.0000,frame_000030.png,0,0,0.000000,not-available,1,0.000000,invalid,1,0.000000,not-available,1,"
                "\"say \"\"hi\"\", ok\",\"\",0.000000,0.000000"}));
}

TEST(FramesCsv, ASceneWithoutBindingsHasTheFrameColumnsOnly) {
  const auto dir = testing::scratch_dir();
  {
    FramesCsv csv(dir / "frames.csv", {});
    csv.row(7, 0.25, "frame.png", true, false, {});
  }
  EXPECT_EQ(testing::read_lines(dir / "frames.csv"),
            (std::vector<std::string>{"frame,time_s,png,link_up,drawn", "7,0.2500,frame.png,1,0"}));
}

TEST(FramesCsv, RowsAreOnDiskAtOnce) {
  const auto dir = testing::scratch_dir();
  FramesCsv csv(dir / "frames.csv", {});
  csv.row(0, 0.0, "a.png", true, true, {});
  EXPECT_EQ(testing::read_lines(dir / "frames.csv").size(), 2u) << "a reader following the file sees the row";
}

// With a display: the presentation columns last; a row waits for its frame's feedback, in order.
TEST(FramesCsv, WithADisplayRowsGainTheirPresentationTime) {
  const auto dir = testing::scratch_dir();
  FramesCsv csv(dir / "frames.csv", {}, false, false, /*presentation=*/true);
  csv.row(4, 0.1, "a.png", true, true, {});
  csv.row(5, 0.2, "b.png", true, true, {});
  EXPECT_EQ(testing::read_lines(dir / "frames.csv").size(), 1u) << "only the header: no feedback yet";
  platform::PresentedFrame shown;
  shown.frame = 4;
  shown.presented_ns = 123456789;
  shown.sequence = 9;
  csv.on_presented(shown);
  csv.not_presented(5);
  csv.row(6, 0.3, "c.png", true, false, {});
  csv.presentation_done();  // frame 6's feedback never came
  EXPECT_EQ(testing::read_lines(dir / "frames.csv"),
            (std::vector<std::string>{"frame,time_s,png,link_up,drawn,presented_ns,refresh_seq",
                                      "4,0.1000,a.png,1,1,123456789,9", "5,0.2000,b.png,1,1,,", "6,0.3000,c.png,1,0,,"}));
}

TEST(FramesCsv, AnUnwritableFileIsNamed) {
  const auto file = testing::scratch_dir() / "missing" / "frames.csv";
  try {
    FramesCsv csv(file, {});
    FAIL() << "no error";
  } catch (const ViewError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ": cannot write");
  }
}

TEST(CsvQuoted, DoublesQuotes) {
  EXPECT_EQ(csv_quoted(""), "\"\"");
  EXPECT_EQ(csv_quoted("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_quoted("\"x\""), "\"\"\"x\"\"\"");
}

TEST(TimingCsv, OneRowPerFrameByStage) {
  const auto dir = testing::scratch_dir();
  {
    TimingCsv timing((dir / "timing.csv").string());
    engine::FrameTiming ft;
    ft.update_ms = 0.12345;
    ft.submit_ms = 1.5;
    ft.gpu_readback_ms = 20.0;
    ft.drawn = true;
    timing.row(0, 0.0, ft);
    ft.drawn = false;
    timing.row(1, 0.0333333, ft);
  }
  EXPECT_EQ(testing::read_lines(dir / "timing.csv"),
            (std::vector<std::string>{"frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn",
                                      "0,0.0000,0.1235,1.5000,20.0000,1", "1,0.0333,0.1235,1.5000,20.0000,0"}));
}

// With a display: each row waits for its frame's presentation feedback; a frame replaced before
// it was shown, or never presented, gets empty cells; the end of the feedback writes the rest.
TEST(TimingCsv, DisplayColumnsWaitForPresentationFeedback) {
  const auto dir = testing::scratch_dir();
  {
    TimingCsv timing((dir / "timing.csv").string(), false, true);
    engine::FrameRecord f;
    f.timing.drawn = true;
    for (std::uint64_t n = 0; n < 4; ++n) {
      f.request.frame = n;
      f.request.t = double(n) / 60;
      f.render_ended_ns = 1'000'000'000 + std::int64_t(n) * 16'000'000;
      timing.on_frame(f);
    }
    EXPECT_EQ(testing::read_lines(dir / "timing.csv").size(), 1u);  // only the header: no feedback yet
    platform::PresentedFrame shown;
    shown.frame = 1;  // frame 0 was never presented (skipped by the display)
    shown.presented_ns = 1'000'000'000 + 16'000'000 + 2'500'000;
    shown.sequence = 7;
    timing.on_presented(shown);
    platform::PresentedFrame gone;
    gone.frame = 2;
    gone.discarded = true;
    timing.on_presented(gone);
    timing.presentation_done();  // frame 3's feedback never came
  }
  EXPECT_EQ(testing::read_lines(dir / "timing.csv"),
            (std::vector<std::string>{
                "frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn,presented_ns,refresh_seq,to_presented_ms",
                "0,0.0000,0.0000,0.0000,0.0000,1,,,", "1,0.0167,0.0000,0.0000,0.0000,1,1018500000,7,2.500",
                "2,0.0333,0.0000,0.0000,0.0000,1,,,", "3,0.0500,0.0000,0.0000,0.0000,1,,,"}));
}

TEST(TimingCsv, NoPathNoFile) {
  TimingCsv timing("");
  timing.row(0, 0.0, engine::FrameTiming{});  // does nothing
  TimingCsv none;
  none.row(0, 0.0, engine::FrameTiming{});
  SUCCEED();
}

TEST(TimingCsv, AnUnwritableFileIsNamed) {
  const auto file = (testing::scratch_dir() / "missing" / "timing.csv").string();
  EXPECT_THROW(
      {
        try {
          TimingCsv timing(file);
        } catch (const ViewError& e) {
          EXPECT_EQ(std::string(e.what()), file + ": cannot write");
          throw;
        }
      },
      ViewError);
}

}  // namespace
}  // namespace meter::runner
