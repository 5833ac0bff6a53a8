// The display-integrity monitor of meter-view: after each drawn frame it reads back only the
// package's safety regions (meter/bridge/integrity.hpp) and judges them with the pure checks of
// meter/engine/integrity_check.hpp against the state the bindings say the frame shows: every
// telltale lit exactly when it must be, every needle at its value's angle, and no region frozen
// (its expected look changed, its pixels did not). A failing telltale or needle is redrawn from a
// safe path (Renderer::redraw_safe). Docs: docs/integrity.md, "The monitor in meter-view".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/engine/integrity_check.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"

namespace meter::view {

struct IntegrityFault {
  std::string region;
  bridge::SafetyKind kind = bridge::SafetyKind::Telltale;
  bool frozen = false;      // the expected look changed, the region's pixels did not
  std::string expected, seen;
  double difference = 0.0;  // Verdict::difference (frozen: the expectation's change)
  std::string describe() const;  // "TT_TurnLeft (telltale): expected on, seen off (...), difference 80.1"
};

// What a region's pixels and expectation were when its pixels last changed (frozen detection).
struct RegionMemory {
  bool valid = false;
  std::uint64_t hash = 0;
  engine::RegionExpectation expected;
};

// True when the look `b` must differ from `a` in pixels: a telltale switched, a needle turned by
// more than max(1 deg, its tolerance) (well above a pixel at its annulus: no sub-pixel move is
// taken for a freeze), a readout's text changed.
bool look_changed(const bridge::SafetyRegion& region, const engine::RegionExpectation& a,
                  const engine::RegionExpectation& b);

// Pure judgement of one frame: `pixels[i]` holds region i's rect (as read back), `expected[i]`
// its expectation. Updates `memory` (one per region). Telltales and needles are checked against
// their expectation; every known region (readouts too) against a freeze. Regions not known yet
// (no value, no failsafe) are not judged.
std::vector<IntegrityFault> judge_frame(const bridge::IntegrityTable& table,
                                        const std::vector<engine::RegionExpectation>& expected,
                                        const std::vector<platform::Image>& pixels, std::vector<RegionMemory>& memory);

class IntegrityMonitor {
 public:
  // Off (reads and checks nothing) when the scene has no safety regions, `enabled` is false, or
  // the frame is drawn at another size than the regions were measured at (off_reason() says why).
  IntegrityMonitor(const engine::Scene& scene, int width, int height, bool enabled = true, bool safe_path = true);

  bool on() const { return on_; }
  const std::string& off_reason() const { return off_reason_; }

  // After the frame was rendered: `drawn` from its FrameTiming. A frame that was not drawn is
  // checked only when the expected looks changed since the last check (a renderer that wrongly
  // skipped is a freeze too). Returns this frame's faults.
  const std::vector<IntegrityFault>& check(engine::Renderer& renderer, const engine::BindingEvaluator& evaluator,
                                           bool drawn);

  std::uint64_t frames_checked() const { return frames_checked_; }
  std::uint64_t faults() const { return faults_; }
  std::uint64_t frozen_faults() const { return frozen_; }
  std::uint64_t safe_redraws() const { return safe_redraws_; }
  const bridge::IntegrityTable& table() const { return table_; }

 private:
  void redraw_safe(engine::Renderer& renderer, std::size_t region, const engine::RegionExpectation& expected);

  const engine::Scene& scene_;
  const bridge::IntegrityTable& table_;
  bool on_ = false, safe_path_ = true;
  std::string off_reason_;
  int height_ = 0;
  std::vector<platform::PixelRegion> boxes_;  // each region's rect in GL window coordinates
  std::vector<RegionMemory> memory_;
  std::vector<engine::RegionExpectation> last_expected_;
  std::vector<IntegrityFault> frame_faults_;
  std::uint64_t frames_checked_ = 0, faults_ = 0, frozen_ = 0, safe_redraws_ = 0;
};

}  // namespace meter::view
