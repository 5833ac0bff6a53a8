// The signal catalog is data: a signal the shipped catalog does not have (a traction battery's
// displayed state of charge) is added to a catalog file, a DBC, a mapping and a scene config, and
// goes from a CAN frame (a candump log the controller replays) over the link to the pixels of the
// needle it drives, with the binaries as built. The view is given no catalog: it takes the
// controller's over the link. A view started with another catalog is refused, naming both files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "candump_line.hpp"
#include "live_run.hpp"
#include "ev_catalog.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "needle.hpp"
#include "process.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;
using meter::testing::read_csv;

namespace {

const std::string kSourceDir = METER_SOURCE_DIR;
const std::string kSoc = meter::testing::kSocName;
// 72.5 % is a raw step of the DBC signal (0.5 % per bit), so the decoded value is exact.
constexpr double kSocPercent = 72.5;
constexpr double kCatalogLogSeconds = 8.0;

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

void write_catalog(const fs::path& file) { write(file, meter::testing::ev_catalog_json().dump(2)); }

void write_dbc(const fs::path& file) {
  write(file, R"(VERSION "ev test"

NS_ :
	BA_DEF_
	BA_

BS_:

BU_: BMS ICL

BO_ 1280 BMS_Status: 8 BMS
 SG_ SOC_Displayed : 0|8@1+ (0.5,0) [0|100] "%" ICL

BA_DEF_ BO_  "GenMsgCycleTime" INT 0 10000;
BA_DEF_DEF_  "GenMsgCycleTime" 0;
BA_ "GenMsgCycleTime" BO_ 1280 100;
)");
}

void write_map(const fs::path& file) {
  write(file, "# The traction battery's state of charge, from the BMS.\n[" + kSoc +
                  "]\nsource = BMS_Status.SOC_Displayed\n");
}

// The minimal gauge's needle, driven by the state of charge: 0..100 % over its 240 degree sweep.
void write_scene_config(const fs::path& file) {
  write(file, R"({
  "format": "meter-scene-config/1",
  "size": [640, 480],
  "camera": "Camera",
  "clear_color": [0.0, 0.0, 0.0, 1.0],
  "time": 0.0,
  "ambient": [0.0, 0.0, 0.0],
  "bindings": [
    {"signal": ")" + kSoc + R"(", "kind": "animation", "animation": "SpeedNeedle",
     "input": [0, 100], "time": [0.0, 10.833333], "smoothing_ms": 0, "failsafe": {"value": 0}}
  ],
  "groups": []
})");
}

void write_log(const fs::path& dbc, const fs::path& file) {
  const auto db = meter::controller::load_dbc(dbc.string());
  const auto* msg = db.find("BMS_Status");
  ASSERT_NE(msg, nullptr);
  std::ofstream out(file);
  const std::int64_t t0_ns = 1'700'000'000'000'000'000LL;
  for (int i = 0; i * 0.1 <= kCatalogLogSeconds + 1e-9; ++i) {
    const std::pair<std::string_view, double> values[] = {{"SOC_Displayed", kSocPercent}};
    out << meter::testing::candump_line(*msg, values, t0_ns + static_cast<std::int64_t>(i) * 100'000'000LL) << "\n";
  }
}

void wait_for_socket(const fs::path& socket, ChildProcess& controller) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!fs::exists(socket)) {
    ASSERT_TRUE(controller.running()) << "meter-controller ended before it listened:\n" << controller.log();
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "meter-controller did not listen in 20 s";
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

struct Vehicle {
  fs::path dir, catalog, dbc, map, scene_config, log, package;
};

Vehicle make_vehicle(const std::string& name) {
  Vehicle v;
  v.dir = fs::path(METER_BINARY_DIR) / "e2e" / name;
  fs::remove_all(v.dir);
  fs::create_directories(v.dir / "frames");
  v.catalog = v.dir / "ev.vss.json";
  v.dbc = v.dir / "ev.dbc";
  v.map = v.dir / "ev.map";
  v.scene_config = v.dir / "ev.scene.json";
  v.log = v.dir / "soc.log";
  v.package = v.dir / "ev.msp";
  write_catalog(v.catalog);
  write_dbc(v.dbc);
  write_map(v.map);
  write_scene_config(v.scene_config);
  write_log(v.dbc, v.log);
  return v;
}

// meter-convert of the minimal gauge's glTF with `config` (and `catalog` unless empty): its exit code.
int convert(const std::string& config, const fs::path& out, const std::string& catalog,
            std::string& log) {
  std::vector<std::string> argv = {built_executable("meter-convert"),
                                   kSourceDir + "/scenes/minimal-gauge/minimal-gauge.glb", "--config", config, "-o",
                                   out.string()};
  if (!catalog.empty()) argv.insert(argv.end(), {"--catalog", catalog});
  ChildProcess p(argv, (out.string() + ".log"));
  const auto rc = p.wait_for(std::chrono::seconds(60));
  log = p.log();
  return rc.value_or(-1);
}

std::vector<std::string> controller_args(const Vehicle& v, const std::string& link) {
  return {built_executable("meter-controller"), "run", "--catalog", v.catalog.string(), "--dbc", v.dbc.string(),
          "--map", v.map.string(), "--input", "log:" + v.log.string(), "--replay", "realtime", "--link", link,
          "--exit-at-end", "--linger", "2"};
}

}  // namespace

TEST(EndToEnd, ANewCatalogSignalGoesFromACanFrameToPixels) {
  ASSERT_EQ(meter::protocol::default_catalog()->find(kSoc), nullptr) << "the shipped catalog already has " << kSoc;
  const Vehicle v = make_vehicle("catalog_signal");
  if (HasFatalFailure()) return;

  // Without the catalog the converter refuses the binding: the signal really is new.
  std::string log;
  ASSERT_EQ(convert(v.scene_config.string(), v.dir / "refused.msp", "", log), 1) << log;
  EXPECT_NE(log.find("\"" + kSoc + "\" is not in the signal catalog protocol/catalog/signals.vss.json"), std::string::npos)
      << log;

  ASSERT_EQ(convert(v.scene_config.string(), v.package, v.catalog.string(), log), 0) << log;

  const fs::path socket = v.dir / "link.sock";
  const std::string link = "unix:" + socket.string();
  ChildProcess controller(controller_args(v, link), (v.dir / "controller.log").string());
  wait_for_socket(socket, controller);
  if (HasFatalFailure()) return;
  // No --catalog: the view waits for the controller, takes its catalog, then loads the scene.
  ChildProcess view({built_executable("meter-view"), "--scene", v.package.string(), "--backend", "egl", "--link",
                     link, "--fps", "10", "--dump-every", "1", "--duration", "5", "--out", (v.dir / "frames").string()},
                    (v.dir / "view.log").string());
  const auto vrc = view.wait_for(std::chrono::seconds(60));
  ASSERT_TRUE(vrc.has_value()) << "meter-view did not finish:\n" << view.log();
  ASSERT_EQ(*vrc, 0) << view.log();
  const auto crc = controller.wait_for(std::chrono::seconds(60));
  ASSERT_TRUE(crc.has_value()) << "meter-controller did not finish:\n" << controller.log();
  EXPECT_EQ(*crc, 0) << controller.log();
  EXPECT_NE(view.log().find("using catalog sent by meter-controller (" + v.catalog.string() + ")"), std::string::npos)
      << view.log();

  // Pixels: the needle stands where the drawn state of charge puts it, and that is the CAN value.
  const meter::testing::NeedleProbe probe{320.0, 240.0, 100.0, 150.0};  // scenes/minimal-gauge README
  int judged = 0;
  for (const auto& r : read_csv(v.dir / "frames" / "frames.csv")) {
    ASSERT_TRUE(r.count(kSoc) && r.count(kSoc + ".status")) << "frames.csv has no column " << kSoc;
    if (r.at("link_up") != "1" || r.at(kSoc + ".status") != "valid") continue;
    const double drawn = std::stod(r.at(kSoc));
    EXPECT_EQ(drawn, kSocPercent) << r.at("png");
    const auto angle = meter::testing::needle_angle_deg(meter::platform::read_png(v.dir / "frames" / r.at("png")), probe);
    ASSERT_TRUE(angle.has_value()) << r.at("png") << ": no needle pixels";
    // 1.5 deg, as in NeedleFollowsSpeedFromLog: the needle centroid is exact to well under a pixel;
    // the margin covers MSAA edge pixels and the colour threshold. 0 % would be -120 deg.
    EXPECT_NEAR(*angle, -120.0 + drawn * 240.0 / 100.0, 1.5) << r.at("png");
    ++judged;
  }
  // 5 s at 10 fps with the controller sending throughout: most frames are live and valid.
  EXPECT_GT(judged, 20) << view.log();
}

TEST(EndToEnd, AViewWithAnotherCatalogIsRefusedNamingBothFiles) {
  const Vehicle v = make_vehicle("catalog_refused");
  if (HasFatalFailure()) return;
  // The minimal gauge binds Vehicle.Speed only: the view's catalog (the shipped file, given
  // explicitly) loads it; the controller runs the EV catalog.
  std::string log;
  ASSERT_EQ(convert(kSourceDir + "/scenes/minimal-gauge/minimal-gauge.scene.json", v.dir / "gauge.msp", "", log), 0)
      << log;
  const fs::path socket = v.dir / "link.sock";
  const std::string link = "unix:" + socket.string();
  ChildProcess controller(controller_args(v, link), (v.dir / "controller.log").string());
  wait_for_socket(socket, controller);
  if (HasFatalFailure()) return;
  const std::string view_catalog = kSourceDir + "/protocol/catalog/signals.vss.json";
  ChildProcess view({built_executable("meter-view"), "--scene", (v.dir / "gauge.msp").string(), "--backend", "egl",
                     "--catalog", view_catalog, "--link", link, "--fps", "10", "--duration", "2", "--out",
                     (v.dir / "frames").string()},
                    (v.dir / "view.log").string());
  ASSERT_EQ(view.wait_for(std::chrono::seconds(60)), 0) << view.log();
  // The same view told to take the controller's catalog instead links up (the log runs 8 s).
  ChildProcess taking({built_executable("meter-view"), "--scene", (v.dir / "gauge.msp").string(), "--backend", "egl",
                       "--catalog", view_catalog, "--catalog-from-controller", "--link", link, "--fps", "10",
                       "--dump-every", "1", "--duration", "2", "--out", (v.dir / "taking").string()},
                      (v.dir / "taking.log").string());
  ASSERT_EQ(taking.wait_for(std::chrono::seconds(60)), 0) << taking.log();
  int live = 0;
  for (const auto& r : read_csv(v.dir / "taking" / "frames.csv")) live += r.at("link_up") == "1" ? 1 : 0;
  EXPECT_GT(live, 0) << taking.log();
  EXPECT_NE(taking.log().find("using catalog sent by meter-controller (" + v.catalog.string() + ")"), std::string::npos)
      << taking.log();
  controller.wait_for(std::chrono::seconds(60));
  for (const std::string& side : {view.log(), controller.log()}) {
    EXPECT_NE(side.find("signal catalog mismatch: controller " + v.catalog.string() + " (hash 0x"), std::string::npos)
        << side;
    EXPECT_NE(side.find("view " + view_catalog + " (hash 0x"), std::string::npos) << side;
  }
  // Not one frame was drawn from the controller's values.
  for (const auto& r : read_csv(v.dir / "frames" / "frames.csv")) EXPECT_EQ(r.at("link_up"), "0") << r.at("frame");
}

TEST(EndToEnd, ABadCatalogFileStopsEachProgramWithTheLoadersMessage) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "e2e" / "catalog_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path bad = dir / "bad.vss.json";
  write(bad, R"({"Vehicle": {"type": "branch", "children": {"Speed": {"type": "sensor", "datatype": "float"}}}})");
  const std::string expected = bad.string() + ": /Vehicle/children/Speed: expected a \"meter_id\" field";
  const std::vector<std::vector<std::string>> runs = {
      {built_executable("meter-controller"), "run", "--catalog", bad.string(), "--map",
       kSourceDir + "/controller/vehicles/demo/demo.map", "--dbc", kSourceDir + "/controller/vehicles/demo/demo.dbc",
       "--input", "log:" + kSourceDir + "/vcan/logs/demo-drive.log"},
      {built_executable("meter-view"), "--scene", (dir / "none.msp").string(), "--catalog", bad.string(), "--set",
       "Vehicle.Speed=1", "--out", dir.string()},
      {built_executable("meter-convert"), kSourceDir + "/scenes/minimal-gauge/minimal-gauge.glb", "--config",
       kSourceDir + "/scenes/minimal-gauge/minimal-gauge.scene.json", "--catalog", bad.string(), "-o",
       (dir / "x.msp").string()},
  };
  int n = 0;
  for (const auto& argv : runs) {
    ChildProcess p(argv, (dir / ("run" + std::to_string(n++) + ".log")).string());
    EXPECT_EQ(p.wait_for(std::chrono::seconds(30)), 1) << argv[0] << ":\n" << p.log();
    EXPECT_NE(p.log().find(expected), std::string::npos) << argv[0] << ":\n" << p.log();
  }
}
