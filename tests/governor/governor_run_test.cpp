// meter-view --target-ms on the cluster: under an injected cost (busy time per drawn pixel, the
// hidden --inject-cost) the governor steps the quality down, and once the cost is removed it comes
// back to full quality, drawing the very image an ungoverned run draws. The drive is a link
// recording played on its own clock (--play), so frame k shows the same state in every run.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "live_run.hpp"
#include "meter/platform/image.hpp"
#include "meter/runner/dump_policy.hpp"
#include "process.hpp"

namespace {

namespace fs = std::filesystem;
namespace mt = meter::testing;

const std::string kSource = METER_SOURCE_DIR;
// One folder per test (ctest may run them at once).
fs::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return fs::path(METER_BINARY_DIR) / "governor-run" / info->name();
}
constexpr int kFps = 30;
constexpr double kSeconds = 6.0;                  // 181 frames
constexpr std::uint64_t kFirst = 30, kLast = 70;  // the injected frames
// A quarter of the config size (1280x480): the test is about the governor's steps, and llvmpipe on
// a shared machine draws the cluster's full frame at the full size in 0.1-0.25 s.
const std::string kSize = "640x240";
constexpr double kPixels = 640.0 * 240.0;

void run(std::vector<std::string> argv, const std::string& log, int timeout_s) {
  mt::ChildProcess p(std::move(argv), (test_dir() / log).string());
  const auto rc = p.wait_for(std::chrono::seconds(timeout_s));
  if (!rc || *rc != 0) throw std::runtime_error(log + ": exit " + (rc ? std::to_string(*rc) : "none (hung)") + "\n" + p.log());
}

struct Prepared {
  fs::path msp, rec;
};

// The cluster with its levels, calibrated when asked (one timed frame per point: the online
// estimate corrects the scale), and the demo drive recorded.
Prepared prepare(bool calibrate) {
  const fs::path dir = test_dir();
  fs::remove_all(dir);
  fs::create_directories(dir);
  Prepared r{dir / "cluster.msp", dir / "drive.rec"};
  run({mt::built_executable("meter-convert"), kSource + "/scenes/cluster/cluster.glb", "--config",
       kSource + "/scenes/cluster/cluster.scene.json", "-o", r.msp.string()},
      "convert.log", 300);
  if (calibrate) run({mt::built_executable("meter-calibrate"), r.msp.string(), "--frames", "1", "--size", kSize}, "calibrate.log", 600);
  run({mt::built_executable("meter-controller"), "run", "--dbc", kSource + "/controller/vehicles/demo/demo.dbc", "--map",
       kSource + "/controller/vehicles/demo/demo.map", "--input", "log:" + kSource + "/vcan/logs/demo-drive.log", "--replay",
       "fast", "--exit-at-end", "--record", r.rec.string(), "--link", "unix:" + (dir / "rec.sock").string(), "--state-dir",
       (dir / "state").string()},
      "record.log", 120);
  return r;
}

// One --play run of the drive, every frame redrawn in full, the last frame dumped.
fs::path play(const Prepared& p, const std::string& tag, const std::vector<std::string>& extra) {
  const fs::path out = test_dir() / tag;
  fs::remove_all(out);
  fs::create_directories(out);
  std::vector<std::string> argv = {mt::built_executable("meter-view"), "--scene", p.msp.string(), "--play",
                                   p.rec.string(), "--fps", std::to_string(kFps), "--duration", std::to_string(kSeconds),
                                   "--size", kSize, "--full-redraw", "--dump-last", "--dump-every", "30", "--out", out.string(),
                                   "--timing-csv", (out / "timing.csv").string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  run(argv, tag + ".log", 600);
  return out;
}

double frame_ms(const std::map<std::string, std::string>& row) {
  return std::stod(row.at("update_ms")) + std::stod(row.at("submit_ms")) + std::stod(row.at("gpu_readback_ms"));
}

bool at_full(const std::map<std::string, std::string>& row) {
  return row.at("units_reduced") == "0" && row.at("msaa") == "4" && std::stod(row.at("scale")) == 1.0;
}

TEST(GovernorRun, StepsDownUnderAnInjectedCostAndComesBackToTheUngovernedImage) {
  const Prepared p = prepare(true);
  const fs::path ref = play(p, "ungoverned", {});
  const auto ref_rows = mt::read_csv(ref / "timing.csv");
  ASSERT_EQ(ref_rows.size(), 181u);
  EXPECT_EQ(mt::read_csv(ref / "frames.csv").front().count("predicted_ms"), 0u) << "governor columns without a governor";
  std::vector<double> ms;
  for (const auto& r : ref_rows)
    if (r.at("drawn") == "1") ms.push_back(frame_ms(r));
  ASSERT_GE(ms.size(), 100u) << "the drive must keep the frames drawn";
  std::size_t drawn_injected = 0;
  for (std::uint64_t k = kFirst; k <= kLast; ++k) drawn_injected += ref_rows.at(k).at("drawn") == "1";
  ASSERT_GE(drawn_injected, 20u) << "the injected frames must be drawn ones (the cost is per drawn pixel)";
  std::nth_element(ms.begin(), ms.begin() + long(ms.size() / 2), ms.end());
  const double median = ms[ms.size() / 2];
  // A target 3x the full-quality median holds full quality with room for this machine's jitter;
  // the injected cost adds 8x the median per frame (per drawn pixel: 640 x 240 at scale 1), so
  // every frame it touches is over the target at any unit level and far over it at full quality.
  const double target = 3.0 * median;
  const double ns_per_pixel = 8.0 * median * 1e6 / kPixels;
  const fs::path gov = play(p, "governed", {"--target-ms", std::to_string(target), "--inject-cost",
                                         std::to_string(ns_per_pixel) + "@" + std::to_string(kFirst) + "-" + std::to_string(kLast)});
  const auto rows = mt::read_csv(gov / "timing.csv");
  ASSERT_EQ(rows.size(), ref_rows.size());
  ASSERT_EQ(rows.front().count("units_reduced"), 1u) << "the governor's columns are missing from the timing CSV";
  EXPECT_EQ(mt::read_csv(gov / "frames.csv").front().count("predicted_ms"), 1u);
  bool stepped_down = false;
  for (std::uint64_t k = kFirst; k <= kLast + 10; ++k) stepped_down = stepped_down || !at_full(rows.at(k));
  EXPECT_TRUE(stepped_down) << "frames " << kFirst << "-" << kLast << " took 9x the median of " << median
                            << " ms against a target of " << target << " ms, and the quality never dropped";
  // Back at full quality for the last 30 frames (the cost ended 110 frames before: the online
  // estimate's 60-frame window has forgotten it 50 frames earlier, and a step up needs at most 8
  // frames since the last change).
  for (std::size_t k = rows.size() - 30; k < rows.size(); ++k)
    EXPECT_TRUE(at_full(rows[k])) << "frame " << k << " units_reduced " << rows[k].at("units_reduced") << " msaa "
                                  << rows[k].at("msaa") << " scale " << rows[k].at("scale");
  const std::string last = meter::runner::png_name(rows.size() - 1);
  const auto a = meter::platform::read_png(gov / last), b = meter::platform::read_png(ref / last);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_TRUE(a.rgba == b.rgba) << last << " differs from the ungoverned run's";
}

}  // namespace

namespace {

TEST(GovernorRun, AMissingCostFileIsAnErrorNamingItAndTheCalibration) {
  const Prepared prep = prepare(false);
  const fs::path out = test_dir() / "no-costs";
  fs::create_directories(out);
  mt::ChildProcess p({mt::built_executable("meter-view"), "--scene", prep.msp.string(), "--play", prep.rec.string(),
                      "--duration", "1", "--size", kSize, "--out", out.string(), "--target-ms", "16.7", "--costs",
                      (out / "absent.costs.json").string()},
                     (test_dir() / "no-costs.log").string());
  const auto rc = p.wait_for(std::chrono::seconds(120));
  ASSERT_TRUE(rc.has_value()) << "meter-view hung";
  EXPECT_EQ(*rc, 1);
  EXPECT_NE(p.log().find((out / "absent.costs.json").string() + ": no cost file for the frame-rate governor"), std::string::npos)
      << p.log();
  EXPECT_NE(p.log().find("meter-calibrate"), std::string::npos) << p.log();
}

}  // namespace

namespace {

// A live view's --dump-last row is the standing frame as drawn, the governor's cells included,
// like every other row of its frames.csv (no controller: the link stays down, the governor runs).
TEST(GovernorRun, ALiveViewsLastDumpCarriesTheGovernorsCells) {
  const fs::path dir = test_dir();
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path msp = dir / "minimal-gauge.msp", out = dir / "live";
  mt::convert_minimal_gauge(msp);
  run({mt::built_executable("meter-calibrate"), msp.string(), "--frames", "1", "--size", kSize}, "calibrate.log", 300);
  run({mt::built_executable("meter-view"), "--scene", msp.string(), "--link", "unix:" + (dir / "none.sock").string(),
       "--catalog-wait", "0", "--duration", "1", "--size", kSize, "--target-ms", "100", "--dump-last", "--out",
       out.string()},
      "live.log", 120);
  const auto rows = mt::read_csv(out / "frames.csv");
  ASSERT_EQ(rows.size(), 1u) << "only the last frame is dumped";
  ASSERT_EQ(rows.front().count("predicted_ms"), 1u) << "the governor's columns are missing";
  EXPECT_FALSE(rows.front().at("predicted_ms").empty()) << "the --dump-last row has no governor cells";
  EXPECT_FALSE(rows.front().at("units_reduced").empty());
}

}  // namespace
