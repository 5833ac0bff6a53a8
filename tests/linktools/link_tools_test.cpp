// The link tools end to end, without a bus: meter-controller replays a candump log into its link;
// meter-linkdump records what it sent while a live meter-view draws it; meter-linkplay then
// replays the recording into a second view. Frames the two views drew at the same signal state
// must be equal pixel for pixel, and every state the live view dwelt in must come back.
//
// Why states and not frame numbers: each view renders at its own clock, so frame N of one run
// and frame N of the other fall at different moments. The minimal gauge draws a pure function of
// its state (Vehicle.Speed value and status, link up; smoothing_ms 0 in its scene config), so two
// frames drawn at the same frames.csv state must be the same image.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "live_run.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/recording.hpp"
#include "meter/protocol/signal_table.hpp"
#include "process.hpp"
#include "speed_log.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;

namespace {

const std::string kSource = METER_SOURCE_DIR;

// Speed steps the controller's damping settles between: 0, 60, 120 km/h, 1.5 s each.
double step_speed_at(double t) { return t < 1.5 ? 0.0 : (t < 3.0 ? 60.0 : 120.0); }
constexpr double kLogSeconds = 4.5;

std::vector<std::string> view_args(const fs::path& dir, const std::string& link, const std::string& out) {
  return {built_executable("meter-view"), "--scene", (dir / "gauge.msp").string(), "--backend", "egl", "--link", link,
          "--fps", "10", "--dump-every", "1", "--duration", "10", "--out", (dir / out).string()};
}

// A frame's drawn state as frames.csv gives it.
using State = std::tuple<std::string, std::string, std::string, std::string>;  // link_up, speed, status, failsafe
std::map<State, std::vector<std::string>> frames_by_state(const fs::path& frames_dir) {
  std::map<State, std::vector<std::string>> out;
  for (const auto& r : meter::testing::read_csv(frames_dir / "frames.csv")) {
    out[{r.at("link_up"), r.at("Vehicle.Speed"), r.at("Vehicle.Speed.status"), r.at("Vehicle.Speed.failsafe")}]
        .push_back(r.at("png"));
  }
  return out;
}

std::string describe(const State& s) {
  return "link_up=" + std::get<0>(s) + " speed=" + std::get<1>(s) + " " + std::get<2>(s) + " failsafe=" + std::get<3>(s);
}

std::vector<std::string> lines_of(const fs::path& file, bool skip_comments) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);)
    if (!(skip_comments && line.rfind("#", 0) == 0) && line.rfind("(", 0) == 0) out.push_back(line);
  return out;
}

}  // namespace

TEST(LinkTools, ReplayedRecordingDrawsTheLiveFramesPixelForPixel) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "linktools" / "roundtrip";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_NO_THROW(meter::testing::write_demo_speed_log(dir / "steps.log", step_speed_at, kLogSeconds));
  ASSERT_NO_THROW(meter::testing::convert_minimal_gauge(dir / "gauge.msp"));

  // Live: controller -> (view A, linkdump) on one link.
  const std::string live_link = "unix:" + (dir / "live.sock").string();
  ChildProcess live_view(view_args(dir, live_link, "live"), (dir / "live-view.log").string());
  ASSERT_NO_THROW(meter::testing::wait_for_first_dump(dir / "live" / "frames.csv", live_view));
  ChildProcess dump({built_executable("meter-linkdump"), "--link", live_link, "-o", (dir / "rec.txt").string(),
                     "--until-closed", "--duration", "60"},
                    (dir / "linkdump.out").string());
  ChildProcess controller({built_executable("meter-controller"), "run", "--dbc",
                           kSource + "/controller/vehicles/demo/demo.dbc", "--map",
                           kSource + "/controller/vehicles/demo/demo.map", "--input", "log:" + (dir / "steps.log").string(),
                           "--replay", "realtime", "--link", live_link, "--state-dir", (dir / "state").string(),
                           "--exit-at-end", "--linger", "2"},
                          (dir / "controller.log").string());
  const auto crc = controller.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(crc.has_value()) << "meter-controller did not finish:\n" << controller.log();
  ASSERT_EQ(*crc, 0) << controller.log();
  const auto drc = dump.wait_for(std::chrono::seconds(20));
  ASSERT_TRUE(drc.has_value()) << "meter-linkdump did not end when the link closed:\n" << dump.log();
  ASSERT_EQ(*drc, 0) << dump.log();
  const auto lrc = live_view.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(lrc.has_value()) << live_view.log();
  ASSERT_EQ(*lrc, 0) << live_view.log();

  // What linkdump printed is what it recorded, and the recording parses.
  const auto printed = lines_of(dir / "linkdump.out", false);
  const auto recorded = lines_of(dir / "rec.txt", true);
  ASSERT_FALSE(recorded.empty()) << dump.log();
  EXPECT_EQ(printed, recorded);
  std::ifstream rec_in(dir / "rec.txt");
  std::string header;
  std::getline(rec_in, header);
  EXPECT_EQ(header, meter::protocol::recording_header(meter::protocol::catalog_hash()));
  rec_in.seekg(0);
  std::vector<meter::protocol::RecordedFrame> frames;
  ASSERT_NO_THROW(frames = meter::protocol::parse_recording(rec_in, (dir / "rec.txt").string()));
  ASSERT_TRUE(std::holds_alternative<meter::protocol::Hello>(frames.front().frame.message)) << recorded.front();
  EXPECT_EQ(std::get<meter::protocol::Hello>(frames.front().frame.message).name, "meter-controller");
  std::size_t deltas = 0, heartbeats = 0;
  for (const auto& f : frames) {
    deltas += std::holds_alternative<meter::protocol::Delta>(f.frame.message);
    heartbeats += std::holds_alternative<meter::protocol::Heartbeat>(f.frame.message);
  }
  EXPECT_TRUE(std::holds_alternative<meter::protocol::Snapshot>(frames.at(1).frame.message)) << recorded.at(1);
  EXPECT_GT(deltas, 10u) << "two speed steps, damped, arrive as many DELTAs";
  EXPECT_GT(heartbeats, 0u) << "--linger 2 with a 1 s link timeout sends heartbeats";
  // The controller ends with --exit-at-end and says so.
  ASSERT_TRUE(std::holds_alternative<meter::protocol::Close>(frames.back().frame.message)) << recorded.back();
  EXPECT_EQ(std::get<meter::protocol::Close>(frames.back().frame.message).reason, meter::protocol::CloseReason::Normal);

  // Replay: linkplay(recording) -> view B.
  const std::string play_link = "unix:" + (dir / "play.sock").string();
  ChildProcess play_view(view_args(dir, play_link, "replay"), (dir / "replay-view.log").string());
  ASSERT_NO_THROW(meter::testing::wait_for_first_dump(dir / "replay" / "frames.csv", play_view));
  ChildProcess play({built_executable("meter-linkplay"), (dir / "rec.txt").string(), "--link", play_link, "--speed",
                     "realtime", "--linger", "2"},
                    (dir / "linkplay.log").string());
  const auto prc = play.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(prc.has_value()) << "meter-linkplay did not finish:\n" << play.log();
  ASSERT_EQ(*prc, 0) << play.log();
  const auto vrc = play_view.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(vrc.has_value()) << play_view.log();
  ASSERT_EQ(*vrc, 0) << play_view.log();

  const auto live = frames_by_state(dir / "live");
  const auto replay = frames_by_state(dir / "replay");
  std::size_t common = 0;
  for (const auto& [state, pngs] : live) {
    const auto it = replay.find(state);
    // The live view dwelt >= 0.5 s (5 frames at 10 fps) in each settled state with the link up: at
    // rest, at the 60 and 120 km/h plateaus (1.5 s each) and through the controller's 2 s linger.
    // The replay holds each state as long, so it must have drawn them too.
    if (std::get<0>(state) == "1" && pngs.size() >= 5) {
      EXPECT_NE(it, replay.end()) << "the replay never drew " << describe(state) << " (" << pngs.size()
                                  << " live frames did)";
    }
    if (it == replay.end()) continue;
    ++common;
    const auto a = meter::platform::read_png(dir / "live" / pngs.front());
    const auto b = meter::platform::read_png(dir / "replay" / it->second.front());
    EXPECT_TRUE(a == b) << describe(state) << ": live " << pngs.front() << " and replayed " << it->second.front()
                        << " differ";
  }
  // At least rest, the two plateaus and the failsafe look before and after the link.
  EXPECT_GE(common, 3u) << "too few states drawn by both views to compare";
}

// A recording with a bad line is refused before anything is served, naming the file and line.
TEST(LinkTools, LinkplayRefusesABadRecordingWithFileAndLine) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "linktools" / "bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream out(dir / "bad.txt");
    out << meter::protocol::recording_header(meter::protocol::catalog_hash()) << "\n"
        << "(1.000000000) HEARTBEAT seq=1 sent=1.000000000\n"
        << "(1.100000000) DELTA seq=2 sent=1.100000000 Vehicle.Speed=12:fine\n";
  }
  ChildProcess play({built_executable("meter-linkplay"), (dir / "bad.txt").string(), "--link",
                     "unix:" + (dir / "never.sock").string(), "--wait-for-view", "0"},
                    (dir / "linkplay.log").string());
  const auto rc = play.wait_for(std::chrono::seconds(20));
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 1) << play.log();
  EXPECT_NE(play.log().find((dir / "bad.txt").string() + ":3: Vehicle.Speed: unknown status 'fine'"), std::string::npos)
      << play.log();
  EXPECT_FALSE(fs::exists(dir / "never.sock")) << "linkplay listened before checking the recording";
}

namespace {

// The state a view holds after applying every SNAPSHOT/DELTA of a recording, as the Subscriber
// applies them (an entry without text clears the text).
meter::protocol::SignalTable final_state(const std::vector<meter::protocol::RecordedFrame>& frames) {
  meter::protocol::SignalTable table;
  for (const auto& r : frames) {
    const std::vector<meter::protocol::SignalUpdate>* list = nullptr;
    if (const auto* s = std::get_if<meter::protocol::Snapshot>(&r.frame.message)) list = &s->signals;
    if (const auto* d = std::get_if<meter::protocol::Delta>(&r.frame.message)) list = &d->signals;
    if (list == nullptr) continue;
    for (const auto& u : *list) table.set(u.id, {u.value, u.status, u.has_text ? u.text : std::string()});
  }
  return table;
}

std::vector<meter::protocol::RecordedFrame> read_recording(const fs::path& file) {
  std::ifstream in(file);
  return meter::protocol::parse_recording(in, file.string());
}

}  // namespace

// linkplay -> linkdump, no view and no GL: the dump of a replay ends in the state the recording
// ends in, at both speeds, and the realtime replay never runs ahead of the recorded timing.
TEST(LinkTools, ReplayIntoLinkdumpEndsInTheRecordedState) {
  using namespace meter::protocol;
  const fs::path dir = fs::path(METER_BINARY_DIR) / "linktools" / "replay_dump";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A hand-made recording over 0.8 s: statuses, a text set and cleared, a value that goes -0.
  const std::int64_t t0 = 5'000'000'000LL;
  auto at = [&](double s) { return t0 + static_cast<std::int64_t>(s * 1e9); };
  auto update = [](SignalId id, double v, SignalStatus st, std::optional<std::string> text = std::nullopt) {
    SignalUpdate u;
    u.id = id;
    u.value = v;
    u.status = st;
    u.has_text = text.has_value();
    u.text = text.value_or("");
    return u;
  };
  const std::vector<RecordedFrame> original = {
      {at(0.0), {1, at(0.0), Hello{Role::Publisher, kProtocolVersion, catalog_hash(), 26, 100, "meter-controller", "", 0}}},
      {at(0.0), {2, at(0.0), Snapshot{true, {update(sig::kSpeed, 0.0, SignalStatus::Valid),
                                             update(sig::kFuelLevel, 0.0, SignalStatus::NotAvailable)}}}},
      {at(0.2), {3, at(0.2), Delta{{update(sig::kSpeed, 33.25, SignalStatus::Valid),
                                    update(sig::kCurrentGear, 3.0, SignalStatus::Valid, "D \"3\"")}}}},
      {at(0.3), {4, at(0.3), Heartbeat{}}},
      {at(0.5), {5, at(0.5), Delta{{update(sig::kFuelLevel, 41.5, SignalStatus::TimedOut)}}}},
      {at(0.8), {6, at(0.8), Delta{{update(sig::kSpeed, -0.0, SignalStatus::Invalid),
                                    update(sig::kCurrentGear, 4.0, SignalStatus::Valid)}}}},
  };
  {
    std::ofstream out(dir / "in.txt");
    out << recording_header(catalog_hash()) << "\n";
    for (const auto& r : original) out << format_line(r) << "\n";
  }
  const auto expected = final_state(original);
  for (const std::string speed : {"realtime", "max"}) {
    SCOPED_TRACE(speed);
    const std::string link = "unix:" + (dir / (speed + ".sock")).string();
    const fs::path out = dir / ("out-" + speed + ".txt");
    ChildProcess play({built_executable("meter-linkplay"), (dir / "in.txt").string(), "--link", link, "--speed", speed,
                       "--linger", "0.5"},
                      (dir / ("play-" + speed + ".log")).string());
    ChildProcess dump({built_executable("meter-linkdump"), "--link", link, "-q", "-o", out.string(), "--until-closed",
                       "--duration", "30"},
                      (dir / ("dump-" + speed + ".log")).string());
    const auto prc = play.wait_for(std::chrono::seconds(30));
    ASSERT_TRUE(prc.has_value()) << play.log();
    ASSERT_EQ(*prc, 0) << play.log();
    const auto drc = dump.wait_for(std::chrono::seconds(30));
    ASSERT_TRUE(drc.has_value()) << dump.log();
    ASSERT_EQ(*drc, 0) << dump.log();
    EXPECT_NE(play.log().find("replayed 4 messages (7 signal updates)"), std::string::npos) << play.log();
    const auto replayed = read_recording(out);
    ASSERT_FALSE(replayed.empty());
    const auto got = final_state(replayed);
    for (const auto& info : catalog()) {
      EXPECT_EQ(got.get(info.id), expected.get(info.id)) << info.name;
    }
    EXPECT_TRUE(std::signbit(got.get(sig::kSpeed).value)) << "-0 came back as +0";
    if (speed == "realtime") {
      // The last update goes out no earlier than 0.8 s after the first (linkplay waits for each
      // recorded time); the dump stamps its receipt, so its span is at least that, less the 1 ms
      // the two receipts' own scheduling can differ by.
      std::vector<std::int64_t> stamps;
      for (const auto& r : replayed)
        if (std::holds_alternative<Delta>(r.frame.message) || std::holds_alternative<Snapshot>(r.frame.message))
          stamps.push_back(r.received_ns);
      ASSERT_GE(stamps.size(), 2u);
      EXPECT_GE(stamps.back() - stamps.front(), 800'000'000LL - 1'000'000LL);
    }
  }
}
