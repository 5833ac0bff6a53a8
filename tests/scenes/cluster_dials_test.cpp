// The defect this guards against: "the speed needle does not point at the printed value". This test reads
// both sides of that sentence from pixels of the real pipeline (meter-convert + meter-view on EGL
// and OSMesa, the committed cluster.glb and its binding file):
//   - the printed scale: the angle of every major tick mark, measured from the rendered frame;
//   - the needle: its angle, measured from the same frame with the needle probe of tests/support.
// Then, for each gauge at known values (speed 0/60/115/260 km/h, 0/3000/8000 rpm, fuel and
// coolant at both ends and in between), the needle must point at the printed position of the value
// (the measured ticks, interpolated linearly between the two ticks around a value that has none),
// and the print itself must sit where the scene script puts it (start + sweep * v / vmax).
//
// What it does not trust: the formula for the needle (the content test checks the keys against the
// formula; this one would still catch a needle and a print that disagree while each follows some
// formula), the binding's signal names (taken from cluster.scene.json, so a binding that maps the
// wrong range or the wrong animation shows up), and a fixed pixel geometry (pivot and scale come
// from the exported camera and nodes, so moving a dial moves the probe with it).
#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "meter/platform/image.hpp"
#include "needle.hpp"
#include "process.hpp"

namespace fs = std::filesystem;
using meter::testing::ChildProcess;
using meter::testing::built_executable;

namespace {

const fs::path kCluster = fs::path(METER_SOURCE_DIR) / "scenes" / "cluster";

// The printed scales as scenes/cluster/build.py draws them (SPEEDO, TACHO, FUEL, COOLANT and
// main_dial() / small_gauge()). Radii are in scene units from the dial centre.
struct Gauge {
  std::string prefix;     // node prefix: <prefix>_Needle, <prefix>_Tick_*
  std::string animation;  // the binding that drives the needle names this animation
  double vmin, vmax;      // printed range
  double start, sweep;    // screen angle (deg, clockwise from up) of vmin, and of vmax - vmin
  double tick_step;       // value between the ticks the probe sees (major ticks; all 5 on small gauges)
  // Ring that holds only those ticks: main dials, between the red zone's outer edge (R - 0.16) and
  // the major ticks' outer end (R - 0.12), beyond the minor ticks (R - 0.22) and the needle tip
  // (R - 0.2); small gauges, between the needle tip (R - 0.02) and the ticks' end (R + 0.06), where
  // the red zone (to R + 0.04) is not white.
  double tick_r0, tick_r1;
  bool white_ticks_only;  // small gauges: only white pixels are print (their red zone shares the ring)
  // Annulus where the probe reads the needle: clear of the hub cap, and on the main dials closer
  // than the small gauge below (whose needle comes within 0.89 of the main pivot), so the small
  // gauge's orange needle never enters it.
  double needle_r0, needle_r1;
};

const std::vector<Gauge> kGauges = {
    {"Speedo", "SpeedNeedle", 0, 260, -120, 240, 20, 2.045, 2.075, false, 0.40, 0.85},
    {"Tacho", "RpmNeedle", 0, 8000, -120, 240, 1000, 2.045, 2.075, false, 0.40, 0.85},
    {"Fuel", "FuelNeedle", 0, 100, -50, 100, 25, 0.605, 0.685, true, 0.20, 0.55},
    {"Coolant", "CoolantNeedle", 50, 130, -50, 100, 20, 0.605, 0.685, true, 0.20, 0.55},
};

// Values each state sets, per gauge prefix. Four frames cover the checked values (0, 60, 115,
// 260 km/h; 0, 3000, 8000 rpm) and both ends plus inner points of the small gauges.
const std::vector<std::map<std::string, double>> kStates = {
    {{"Speedo", 0}, {"Tacho", 0}, {"Fuel", 0}, {"Coolant", 50}},
    {{"Speedo", 60}, {"Tacho", 3000}, {"Fuel", 12.5}, {"Coolant", 90}},
    {{"Speedo", 115}, {"Tacho", 8000}, {"Fuel", 60}, {"Coolant", 115}},
    {{"Speedo", 260}, {"Tacho", 6500}, {"Fuel", 100}, {"Coolant", 130}},
};

// Tolerances, in degrees on screen.
// Print vs the script's formula, tick angles about the projected dial centre: a tick's centroid is
// exact up to anti-aliasing noise (<= 0.1 deg) except that perspective shows the raised ticks (top
// at z 0.014..0.016, walls visible off axis) up to 0.4 px towards the frame's edge, which is 0.38
// deg on the small gauges' 64 px ring (measured: fuel/coolant middle tick -0.38/+0.38 deg).
constexpr double kPrintTolDeg = 0.5;
// Needle vs print as authored: the needle's angle about its own projected pivot against the print's
// angle about the projected dial centre. The camera looks straight at the dial plane, so each plane
// parallel to it projects by a uniform scale and the two angles are the 3D ones: the only error
// left is the centroids' (<= 0.1 deg) and the tick perspective above (<= 0.4 deg). 0.5 deg is
// 0.54 km/h, 17 rpm, 0.5 % fuel, 0.4 degC; the defect in the report was ~9 deg (10 km/h).
constexpr double kNeedleTolDeg = 0.5;
// Needle vs print as the camera sees them: the needle floats above the face (0.12, small gauges
// 0.06) and the dials sit 3.75 off the camera axis, so perspective moves the needle's pivot
// sideways against the print by d px (1.1..2.3 px); seen from the needle's pivot, a tick at r px
// moves by up to atan(d / r). The visual check allows that bound on top of kNeedleTolDeg.

double angle_diff(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

// Pixel projection of the exported perspective camera. The camera looks straight down glTF -Y at
// the dial plane (checked), so a point's pixel depends only on its offset from the camera axis
// and its depth: pixel = centre + f * offset / depth, f = (H / 2) / tan(yfov / 2).
struct Projection {
  double cam_x = 0, cam_y = 0, cam_z = 0, f = 0, w = 0, h = 0;
  // glTF (x, y, z) with y towards the camera; screen right = +x, screen up = -z.
  std::array<double, 2> pixel(const std::vector<double>& t) const {
    const double depth = cam_y - t.at(1);
    return {w / 2 + f * (t.at(0) - cam_x) / depth, h / 2 + f * (t.at(2) - cam_z) / depth};
  }
  double px_per_unit(double y) const { return f / (cam_y - y); }
};

struct SceneGeometry {
  Projection proj;
  std::map<std::string, std::vector<double>> translation;  // node name -> glTF translation
};

SceneGeometry load_geometry(int width, int height) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  const fs::path glb = kCluster / "cluster.glb";
  if (!loader.LoadBinaryFromFile(&m, &err, &warn, glb.string())) {
    throw std::runtime_error(glb.string() + ": " + err);
  }
  SceneGeometry g;
  for (const auto& n : m.nodes) g.translation[n.name] = n.translation;
  for (const auto& n : m.nodes) {
    if (n.camera < 0) continue;
    const auto& cam = m.cameras.at(static_cast<std::size_t>(n.camera));
    if (cam.type != "perspective") throw std::runtime_error("cluster camera is not perspective");
    // Looking down -Y: rotation of -90 deg about X, i.e. (x, y, z, w) = (-s, 0, 0, s).
    const auto& r = n.rotation;
    if (r.size() != 4 || std::abs(r[0] + std::sqrt(0.5)) > 1e-4 || std::abs(r[3] - std::sqrt(0.5)) > 1e-4) {
      throw std::runtime_error("cluster camera does not look straight at the dial plane");
    }
    g.proj = {n.translation.at(0), n.translation.at(1), n.translation.at(2),
              (height / 2.0) / std::tan(cam.perspective.yfov / 2.0), double(width), double(height)};
    return g;
  }
  throw std::runtime_error(glb.string() + ": no camera node");
}

// Signal that drives each needle animation, from the binding file.
std::map<std::string, std::string> animation_signals() {
  std::ifstream in(kCluster / "cluster.scene.json");
  const auto cfg = nlohmann::json::parse(in);
  std::map<std::string, std::string> out;
  for (const auto& b : cfg.at("bindings")) {
    if (b.value("kind", "") == "animation") out[b.at("animation").get<std::string>()] = b.at("signal").get<std::string>();
  }
  return out;
}

bool is_print(const std::uint8_t* p, bool white_only) {
  // White print (0.85 emissive) reaches >= 230 in every channel; red print (0.9, 0.03, 0.01) red
  // >= 200. The dark, normal-mapped face stays below 120 even in the spot lights' highlight, so 170
  // separates them with margin on both sides; anti-aliased tick edges fall either way evenly.
  if (white_only) return p[0] >= 170 && p[1] >= 170 && p[2] >= 170;
  return p[0] >= 170;
}

// Angle (clockwise from up, about (ox, oy)) of the centroid of print pixels inside the ring
// r0..r1 around the dial centre (cx, cy) and within +-window degrees of `near`. nullopt if fewer
// than min_pixels qualify.
std::optional<double> tick_angle(const meter::platform::Image& img, double cx, double cy, double r0,
                                 double r1, double near, double window, bool white_only, double ox,
                                 double oy, int* pixels) {
  double sx = 0, sy = 0;
  int n = 0;
  for (int y = std::max(0, int(cy - r1)); y < std::min(img.height, int(cy + r1) + 2); ++y) {
    for (int x = std::max(0, int(cx - r1)); x < std::min(img.width, int(cx + r1) + 2); ++x) {
      const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
      const double r = std::hypot(dx, dy);
      if (r < r0 || r > r1) continue;
      const double a = std::atan2(dx, -dy) * 180.0 / M_PI;
      if (std::abs(angle_diff(a, near)) > window) continue;
      if (!is_print(img.pixel(x, y), white_only)) continue;
      sx += x + 0.5;
      sy += y + 0.5;
      ++n;
    }
  }
  *pixels = n;
  if (n < 6) return std::nullopt;
  return std::atan2(sx / n - ox, -(sy / n - oy)) * 180.0 / M_PI;
}

class ClusterDials : public ::testing::TestWithParam<std::string> {};

TEST_P(ClusterDials, NeedlesPointAtThePrintedValue) {
  const std::string backend = GetParam();
  const fs::path dir = fs::path(METER_BINARY_DIR) / "tests" / "scenes" / ("dials." + backend);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path msp = dir / "cluster.msp";
  {
    ChildProcess convert({built_executable("meter-convert"), (kCluster / "cluster.glb").string(), "--config",
                          (kCluster / "cluster.scene.json").string(), "-o", msp.string(), "-q"},
                         (dir / "convert.log").string());
    const auto rc = convert.wait_for(std::chrono::seconds(90));
    ASSERT_TRUE(rc.has_value()) << "meter-convert hung";
    ASSERT_EQ(*rc, 0) << convert.log();
  }
  const auto signals = animation_signals();
  std::optional<SceneGeometry> geo;

  for (std::size_t s = 0; s < kStates.size(); ++s) {
    const std::string png = "state" + std::to_string(s) + ".png";
    std::vector<std::string> args = {built_executable("meter-view"), "--scene", msp.string(), "--backend",
                                     backend, "--out", dir.string(), "--png", png};
    for (const auto& [prefix, value] : kStates[s]) {
      const Gauge& g = *std::find_if(kGauges.begin(), kGauges.end(), [&](const Gauge& x) { return x.prefix == prefix; });
      ASSERT_TRUE(signals.count(g.animation)) << "cluster.scene.json: no binding drives " << g.animation;
      args.push_back("--set");
      args.push_back(signals.at(g.animation) + "=" + std::to_string(value));
    }
    ChildProcess view(args, (dir / ("view" + std::to_string(s) + ".log")).string());
    const auto rc = view.wait_for(std::chrono::seconds(90));
    ASSERT_TRUE(rc.has_value()) << "meter-view hung";
    ASSERT_EQ(*rc, 0) << view.log();
    const auto img = meter::platform::read_png(dir / png);
    if (!geo) geo = load_geometry(img.width, img.height);

    for (const Gauge& g : kGauges) {
      const double v = kStates[s].at(g.prefix);
      const std::string where = backend + " " + png + " " + g.prefix + " at " + std::to_string(v);
      // The print lies on the face (z ~ 0.004..0.016), the needle above it: each is projected
      // from its own node, so perspective is part of what is measured, not assumed away.
      const auto& tick_t = geo->translation.at(g.prefix + "_Tick_" + (g.white_ticks_only ? std::string("0") : std::string("00000")));
      const auto& needle_t = geo->translation.at(g.prefix + "_Needle");
      const auto c = geo->proj.pixel(tick_t);
      const auto p = geo->proj.pixel(needle_t);
      const double k_print = geo->proj.px_per_unit(tick_t.at(1));
      const double k_needle = geo->proj.px_per_unit(needle_t.at(1));

      // Printed ticks, each measured twice: about the dial centre (the print as authored) and
      // about the needle's projected pivot (the print as the camera shows it next to the needle).
      std::map<double, double> authored, seen;  // tick value -> angle
      for (double t = g.vmin; t <= g.vmax + 1e-9; t += g.tick_step) {
        const double formula = g.start + g.sweep * (t - g.vmin) / (g.vmax - g.vmin);
        int n = 0;
        // Window: under half the spacing between the ticks in the ring (main 18.5 deg, small
        // 25 deg), so a neighbour never leaks in and a misplaced tick is still found.
        const double window = 8.0;
        const double r0 = g.tick_r0 * k_print, r1 = g.tick_r1 * k_print;
        const auto about_centre = tick_angle(img, c[0], c[1], r0, r1, formula, window, g.white_ticks_only, c[0], c[1], &n);
        ASSERT_TRUE(about_centre.has_value()) << where << ": no print found for tick " << t << " (" << n << " px)";
        EXPECT_NEAR(angle_diff(*about_centre, formula), 0.0, kPrintTolDeg)
            << where << ": tick " << t << " printed at " << *about_centre << " deg, the script puts it at " << formula;
        authored[t] = *about_centre;
        seen[t] = *tick_angle(img, c[0], c[1], r0, r1, formula, window, g.white_ticks_only, p[0], p[1], &n);
      }
      // Printed position of v: its tick, or linear between the ticks around it (a linear scale;
      // the ticks were just checked against the linear formula).
      auto printed_at = [&](const std::map<double, double>& ticks) {
        auto hi = ticks.lower_bound(v - 1e-9);
        if (hi == ticks.end()) throw std::runtime_error(where + ": value above the printed scale");
        if (std::abs(hi->first - v) <= 1e-9) return hi->second;
        if (hi == ticks.begin()) throw std::runtime_error(where + ": value below the printed scale");
        auto lo = std::prev(hi);
        return lo->second + angle_diff(hi->second, lo->second) * (v - lo->first) / (hi->first - lo->first);
      };
      const double want_authored = printed_at(authored), want_seen = printed_at(seen);
      // Orange needle, base and emissive (1, 0.1, 0): red saturated, green 20..140 on the lit and
      // the shaded flank, blue low; white and red print never pass.
      meter::testing::NeedleProbe probe{p[0], p[1], g.needle_r0 * k_needle, g.needle_r1 * k_needle, 200, 140, 60};
      const auto got = meter::testing::needle_angle_deg(img, probe);
      ASSERT_TRUE(got.has_value()) << where << ": no needle pixels";
      const double err = angle_diff(*got, want_authored), err_seen = angle_diff(*got, want_seen);
      // Perspective bound for the visual check (see kNeedleTolDeg): pivot offset over the ring.
      const double parallax = std::atan2(std::hypot(p[0] - c[0], p[1] - c[1]), g.tick_r0 * k_print) * 180.0 / M_PI;
      std::printf("%-6s %s %-7s %7.1f: needle %8.3f, print %8.3f (%+6.3f); as seen %8.3f (%+6.3f, bound %.2f)\n",
                  backend.c_str(), png.c_str(), g.prefix.c_str(), v, *got, want_authored, err, want_seen, err_seen,
                  parallax);
      EXPECT_NEAR(err, 0.0, kNeedleTolDeg)
          << where << ": needle at " << *got << " deg, the print shows this value at " << want_authored << " deg";
      EXPECT_NEAR(err_seen, 0.0, kNeedleTolDeg + parallax)
          << where << ": as the camera sees it, the needle at " << *got << " deg and the print at " << want_seen;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, ClusterDials, ::testing::Values("egl", "osmesa"),
                         [](const auto& info) { return info.param; });

}  // namespace
