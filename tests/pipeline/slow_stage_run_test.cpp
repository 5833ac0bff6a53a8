// --stats names the bottleneck on a real run: each stage of the live pipeline in turn is made
// slower by --inject-slow-stage STAGE:60 (a sleep inside its busy span, 3 frame periods at
// --fps 50), and the last --stats window of that run must name that stage and no other (the
// first windows hold the start-up: the first frame compiles the programs). The views run side by
// side (they mostly sleep), without a controller: every stage runs each frame, drawn or skipped.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "live_run.hpp"
#include "process.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;

namespace {

const std::vector<std::string> kStages = {"intake", "evaluate", "plan", "render", "readback", "check", "encode"};

// The last window's bottleneck ("...; encode busy 89 % (its thread 90 %), readback waited 80 % on
// it: encode is the bottleneck"), or "" when the log has none. The exit line (the whole run) is
// the last in the log: the one before it is taken.
std::string named_bottleneck(const std::string& log, std::string& line) {
  static const std::regex stats_line(R"(meter-view: stats [0-9.]+ s: [^\n]*; ([^\n]*): (\w+) is the bottleneck)");
  std::vector<std::pair<std::string, std::string>> found;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), stats_line); it != std::sregex_iterator(); ++it)
    found.emplace_back((*it)[0].str(), (*it)[2].str());
  if (found.size() < 2) return "";
  line = found[found.size() - 2].first;
  return found[found.size() - 2].second;
}

TEST(PipelineSlowStage, EachInjectedSlowStageIsNamedTheBottleneck) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "pipeline" / "slow_stage";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_NO_THROW(meter::testing::convert_minimal_gauge(dir / "gauge.msp"));
  std::vector<std::unique_ptr<ChildProcess>> views;
  for (const auto& stage : kStages) {
    const fs::path out = dir / stage;
    fs::create_directories(out);
    std::vector<std::string> argv{built_executable("meter-view"), "--scene", (dir / "gauge.msp").string(), "--backend",
                                  "egl", "--size", "320x240", "--link", "unix:" + (out / "no-controller.sock").string(),
                                  "--fps", "50", "--duration", "4", "--out", out.string(), "--stats",
                                  "--stats-interval", "0.5", "--inject-slow-stage", stage + ":60"};
    // The writer's stages and the readback work only on dumped frames: every frame is dumped there,
    // the writer's buffer blocking as CUBE's buffers did. Elsewhere nothing is dumped, so a PNG
    // encode on a loaded host does not compete with the slowed stage.
    if (stage == "readback" || stage == "check" || stage == "encode")
      argv.insert(argv.end(), {"--dump-every", "1", "--dump-policy", "block"});
    views.push_back(std::make_unique<ChildProcess>(argv, (out / "view.log").string()));
  }
  for (std::size_t i = 0; i < kStages.size(); ++i) {
    const auto rc = views[i]->wait_for(std::chrono::seconds(60));
    ASSERT_TRUE(rc.has_value()) << kStages[i] << ": meter-view hung\n" << views[i]->log();
    ASSERT_EQ(*rc, 0) << views[i]->log();
    const std::string log = views[i]->log();
    std::string line;
    EXPECT_EQ(named_bottleneck(log, line), kStages[i]) << "the run slowed at " << kStages[i] << ":\n" << log;
    EXPECT_NE(line.find(kStages[i] + " busy"), std::string::npos) << line;
  }
}

}  // namespace
