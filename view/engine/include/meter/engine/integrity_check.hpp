// The pure checks of display integrity (regions: meter/bridge/integrity.hpp): a frame's pixels in
// one safety region against the state the bindings say it must show. No GL: the runtime monitor
// in meter-view (on the regions it read back) and meter-verify (on dumped PNGs) call the same
// functions, so both judge a frame the same way. Docs and measured bounds: docs/integrity.md.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// RGBA8 pixels of a frame or of a part of it. (x0, y0) is the frame position of the first pixel,
// so a view of the whole frame has x0 = y0 = 0 and a view of a region read back alone has
// (x0, y0) = (rect.x, rect.y). Rows top-down (PNG order); `stride` bytes between rows (0 = 4 *
// width). The checks read only pixels inside the region's rect; a view that does not hold them
// all gives a failed verdict saying so (never an out-of-range read).
struct RgbaView {
  const std::uint8_t* data = nullptr;
  int width = 0, height = 0;
  int x0 = 0, y0 = 0;
  int stride = 0;
  bool covers(const PixelRect& r) const;
  const std::uint8_t* pixel(int frame_x, int frame_y) const;  // caller ensures it is inside
};

struct Verdict {
  bool ok = false;
  std::string expected;   // e.g. "on", "82.0 km/h at -44.6 deg", "\"82\""
  std::string seen;       // e.g. "off (mean 12,12,14)", "-41.5 deg", "glyphs differ"
  double difference = 0;  // telltale: colour distance 0..255; needle: degrees; readout: pixels
};

// What a region must show, derived from the binding evaluator's state after the update the frame
// was drawn with (its outputs: visibility, emissive / colour, animation time, texts).
struct RegionExpectation {
  bool known = false;     // false: nothing drives it yet (no value, no failsafe): not checked
  bool lit = false;       // telltale
  double value = 0.0;     // needle: the value drawn (smoothed); readout: the value formatted
  double time = 0.0;      // needle: the animation time the binding evaluated
  double angle_deg = 0.0; // needle: expected_angle(time)
  std::string text;       // readout: the text drawn
};

// The expectations of one table's regions with every name they use (nodes, materials,
// animations, the scene's node tree) resolved once, for a caller that asks on every frame.
// `table` and `scene` must outlive it; `scene` is the one the evaluators are built on.
class ExpectedStates {
 public:
  ExpectedStates(const IntegrityTable& table, const Scene& scene);
  // One per region, in table order, into `out` (its storage is reused).
  void evaluate(const BindingEvaluator& evaluator, std::vector<RegionExpectation>& out) const;
  RegionExpectation of(std::size_t region, const BindingEvaluator& evaluator) const;

 private:
  struct Resolved {
    std::vector<int> nodes, materials;  // per binding of the region: its node / material index (-1: none)
    int node = -1;                      // the region's node
    int animation = -1;                 // needle: its animation
    bool missing = false;               // a name the scene does not have: never known
  };
  bool visible(const BindingOutputs& outputs, int node) const;
  const IntegrityTable& table_;
  const Scene& scene_;
  std::vector<int> parent_;  // per node, -1 for a root
  std::vector<Resolved> resolved_;
};

// One expectation per region, in table order. `scene` is the one the evaluator was built on.
std::vector<RegionExpectation> expected_states(const IntegrityTable& table, const Scene& scene,
                                               const BindingEvaluator& evaluator);
RegionExpectation expected_state(const SafetyRegion& region, const Scene& scene, const BindingEvaluator& evaluator);

// An angle difference in degrees brought into [-180, 180].
double wrap_degrees(double d);

// Needle: the angle (deg clockwise from up, unwrapped like the samples) the table gives for an
// animation time, linear between samples, clamped at the ends.
double expected_angle(const NeedleModel& needle, double time);
// Needle: the angle read from pixels (centroid of needle pixels in the annulus), or nullopt with
// fewer than min_pixels needle pixels.
std::optional<double> needle_angle(const SafetyRegion& region, const RgbaView& frame, int* pixels = nullptr);
// Needle: the pixels the angle is read from (the needle's colour box, inside the annulus and the
// sector), counted inside `bands` (disjoint parts of the region's rect, `views[j]` holding
// `bands[j]`; pixels outside the rect never count): their number, the sums of their columns and
// rows (integers: the same pixels give the same sums whatever parts of the frame hold them), and
// how many lie within kNeedleWindowEdge pixels of the bands' outline where it is not a side of the
// rect (there the needle may go on outside the bands).
struct NeedlePixels {
  int count = 0;
  std::int64_t sum_x = 0, sum_y = 0;
  int at_edge = 0;
  bool operator==(const NeedlePixels&) const = default;
};
NeedlePixels needle_pixels(const SafetyRegion& region, std::span<const RgbaView> views, std::span<const PixelRect> bands);
NeedlePixels needle_pixels(const SafetyRegion& region, const RgbaView& frame, const PixelRect& within);
// The centroid's angle (deg clockwise from up) of those pixels, nullopt below min_pixels.
std::optional<double> centroid_angle(const NeedleModel& needle, const NeedlePixels& pixels);

// The part of a needle's rect the runtime monitor reads on a frame (docs/integrity.md, "Cost"):
// the segment from r_min to r_max at the expected angle widened on every side by
// r_max * sin(kNeedleWindowSlackDeg) + half_width + kNeedleWindowEdge pixels, as disjoint bands
// kNeedleWindowBand pixels long across the segment's longer screen axis (each band the box of
// its piece of the widened segment), clipped to the rect. A needle up to half_width pixels wide
// on each side of its axis and within the slack of the expected angle lies inside them, off
// their edge; a needle further off, or wider, reaches their outline and check_needle_window
// then does not decide.
inline constexpr double kNeedleWindowSlackDeg = 0.5;
inline constexpr int kNeedleWindowEdge = 2;
inline constexpr int kNeedleWindowBand = 48;
std::vector<PixelRect> needle_window(const SafetyRegion& region, double expected_deg, int half_width);
// check_needle on the window's bands only (`views[j]` holds `bands[j]`). It decides only when the
// needle it finds there is within the tolerance and reaches no inner part of the outline (no
// needle pixel within kNeedleWindowEdge of it); then its verdict is check_needle's on the whole
// rect unless the rect holds needle-coloured pixels in the annulus and sector outside the bands
// and not joined to the needle (a second needle). Anything else (a needle off by more than the
// tolerance, at an old angle, missing, cut by the outline) is nullopt: read the whole rect and
// call check_needle. `pixels` (optional) receives what was counted in the bands.
std::optional<Verdict> check_needle_window(const SafetyRegion& region, std::span<const RgbaView> views,
                                           std::span<const PixelRect> bands, double expected_deg,
                                           NeedlePixels* pixels = nullptr);

// Telltale: mean colour over the lamp mask.
std::array<double, 3> lamp_mean(const SafetyRegion& region, const RgbaView& frame);

// The checks. Each reads only region.rect.
Verdict check_telltale(const SafetyRegion& region, const RgbaView& frame, bool expected_lit);
Verdict check_needle(const SafetyRegion& region, const RgbaView& frame, double expected_angle_deg,
                     const std::string& expected_label = "");
// Readout: `reference` holds the same rect rendered with the expected text (the engine's own text
// path, e.g. meter-verify's re-render of the frame's state).
Verdict check_readout(const SafetyRegion& region, const RgbaView& frame, const RgbaView& reference,
                      const std::string& expected_text);
// Dispatch on region.kind with the expectation (readouts need `reference`; without one a readout
// verdict fails saying so).
Verdict check_region(const SafetyRegion& region, const RgbaView& frame, const RegionExpectation& expected,
                     const RgbaView* reference = nullptr);

// FNV-1a 64 over the region's RGBA pixels, row by row: equal hashes on two frames whose
// expectation changed mean the region did not change (a frozen frame).
std::uint64_t region_hash(const SafetyRegion& region, const RgbaView& frame);

}  // namespace meter::engine
