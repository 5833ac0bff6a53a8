// Display integrity: the safety regions of a scene (telltales, needles, readouts) and what each
// must look like, as plain data. The converter measures them from the engine's own offscreen
// renders at the scene config's size (meter/convert/integrity.hpp) and stores them in the package
// after the scene config text; the runtime monitor in meter-view and the offline checker
// meter-verify read them and judge frames with the pure checks of meter/engine/integrity_check.hpp.
// Docs: docs/integrity.md.
//
// Coordinates are pixels of a frame at IntegrityTable::width x height, origin top-left, y down
// (PNG row order, platform::Image rows). Colours are sRGB-encoded 0..255 as stored in frames.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "meter/bridge/scene_config.hpp"

namespace meter::bridge {

struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  bool contains(int px, int py) const { return px >= x && py >= y && px < x + width && py < y + height; }
  bool operator==(const PixelRect&) const = default;
};

enum class SafetyKind { Telltale, Needle, Readout };
const char* to_string(SafetyKind kind);  // "telltale" | "needle" | "readout"

// One look a telltale region can have, measured from a render in that state: the mean sRGB colour
// of the lamp pixels (TelltaleModel::mask) and whether it is the lit look.
struct TelltaleLook {
  std::string name;            // "on", "off" (node hidden), "unlit" (shown, colour at its off value)
  bool lit = false;
  std::array<double, 3> mean{0, 0, 0};  // 0..255
  bool operator==(const TelltaleLook&) const = default;
};

struct TelltaleModel {
  // Lamp pixels: one byte per pixel of the region's rect, row-major, non-zero where the on render
  // differs from an off render. Only these pixels are averaged.
  std::vector<std::uint8_t> mask;
  std::vector<TelltaleLook> looks;  // at least one lit and one not lit
  // A frame's mean over the mask may differ from the expected look's by at most this much in any
  // channel (0..255); measured across backends and MSAA settings (docs/integrity.md).
  double tolerance = 0.0;
  bool operator==(const TelltaleModel&) const = default;
};

// One point of the needle's mapping: animation time (what the binding evaluates a value to) ->
// the screen angle the needle shows, degrees clockwise from straight up about the pivot,
// measured from a render at that time. Angles are unwrapped (continuous along the table).
struct NeedleSample {
  double time = 0.0;
  double value = 0.0;  // the signal value the binding maps to `time` (for reports)
  double angle_deg = 0.0;
  bool operator==(const NeedleSample&) const = default;
};

struct NeedleModel {
  std::string animation;           // the binding's animation
  double pivot_x = 0, pivot_y = 0;  // projected rotation axis, frame pixels
  double r_min = 0, r_max = 0;     // annulus (pixels from the pivot) where only this needle moves
  // A pixel is a needle pixel when each channel lies in [color_min, color_max] (learnt from the
  // needle's fully covered pixels; no pixel of the annulus without the needle passes).
  std::array<int, 3> color_min{0, 0, 0}, color_max{255, 255, 255};
  int min_pixels = 0;              // fewer needle pixels than this: no needle seen
  // Only pixels within sector_half_deg of sector_center_deg (screen angle about the pivot) are
  // read: the needle's sweep plus a margin, so a neighbouring gauge outside it never counts.
  // 180 = the whole annulus.
  double sector_center_deg = 0.0, sector_half_deg = 180.0;
  std::vector<NeedleSample> samples;  // increasing time
  double tolerance_deg = 0.0;      // |seen - expected| bound, measured (docs/integrity.md)
  bool operator==(const NeedleModel&) const = default;
};

struct ReadoutModel {
  int anchor_x = 0, baseline_y = 0;  // text anchor, frame pixels
  int size_px = 0;
  TextAlign align = TextAlign::Left;
  std::string format;                // the binding's printf format
  // A frame matches a reference render of the expected text when at most this many pixels of the
  // rect differ by more than kReadoutInkStep in some channel (measured, docs/integrity.md).
  int tolerance_pixels = 0;
  bool operator==(const ReadoutModel&) const = default;
};

struct SafetyRegion {
  std::string name;              // unique in the table, e.g. "TT_TurnLeft", "Speedo_Needle"
  SafetyKind kind = SafetyKind::Telltale;
  std::string signal;            // catalog name of the signal it shows
  std::vector<int> bindings;     // indices into SceneConfig::bindings that drive it
  std::string node;              // telltale: visibility node (or the lit material's node);
                                 // needle: the rotated node; readout: the text node
  std::vector<std::string> materials;  // telltale: materials its emissive / colour bindings set
  PixelRect rect;                // where to read it, clipped to the frame
  TelltaleModel telltale;        // kind == Telltale
  NeedleModel needle;            // kind == Needle
  ReadoutModel readout;          // kind == Readout
  bool operator==(const SafetyRegion&) const = default;
};

struct IntegrityTable {
  std::vector<SafetyRegion> regions;
  int width = 0, height = 0;     // the frame size the regions are for (the scene config's)
  bool empty() const { return regions.empty(); }
  bool operator==(const IntegrityTable&) const = default;
};

// Readout comparison: a pixel differs when some channel differs by more than this (0..255). Text
// antialiasing and sRGB rounding move edge pixels by a few steps; a glyph's ink changes by >100.
inline constexpr int kReadoutInkStep = 64;

}  // namespace meter::bridge
