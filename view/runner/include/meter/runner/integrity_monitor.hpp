// The display-integrity monitor of meter-view: after each drawn frame it reads back only the
// package's safety regions (meter/bridge/integrity.hpp) and judges them with the pure checks of
// meter/engine/integrity_check.hpp against the state the bindings say the frame shows: every
// telltale lit exactly when it must be, every needle at its value's angle, and no region frozen
// (its expected look changed, its pixels did not). A failing telltale or needle is redrawn from a
// safe path (Renderer::redraw_safe). Docs: docs/integrity.md, "The monitor in meter-view".
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <optional>
#include <string>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/engine/integrity_check.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"

namespace meter::runner {

struct IntegrityFault {
  std::string region;
  bridge::SafetyKind kind = bridge::SafetyKind::Telltale;
  bool frozen = false;      // the expected look changed, the region's pixels did not
  std::string expected, seen;
  double difference = 0.0;  // Verdict::difference (frozen: the expectation's change)
  std::string describe() const;  // "TT_TurnLeft (telltale): expected on, seen off (...), difference 80.1"
};

// What a region showed and was expected to show when what it shows last changed (frozen
// detection). What it shows: a telltale's or readout's pixels themselves (not engine::
// region_hash: equal bytes are compared at memcmp speed, faster than hashing them, and exactly);
// a needle's needle pixels (engine::NeedlePixels: their count and sums, equal exactly when the
// same pixels are the needle's, wherever the needle was read from).
struct RegionMemory {
  bool valid = false;
  std::vector<std::uint8_t> pixels;
  engine::RegionExpectation expected;
};

// What was read back of one region in a frame: its whole rect (one image), or for a needle only
// the bands of its window (engine::needle_window), one image each. No image: not read.
struct RegionRead {
  std::vector<platform::Image> images;
  std::vector<bridge::PixelRect> rects;  // frame position and size of each image
  bool read() const { return !images.empty() && !images.front().empty(); }
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

// judge_frame on what was read: a needle read through its window is judged there when the window
// decides (engine::check_needle_window); when it cannot, the region is left unjudged (no fault,
// memory untouched) and its index added to `undecided`: read its whole rect and judge it again.
std::vector<IntegrityFault> judge_reads(const bridge::IntegrityTable& table,
                                        const std::vector<engine::RegionExpectation>& expected,
                                        std::vector<RegionRead>& reads, std::vector<RegionMemory>& memory,
                                        std::vector<std::size_t>* undecided = nullptr);

// Where check() reads the regions it judges (GL window coordinates of the frame, rows top-down):
// unset, the renderer's resolved target; with a display, the back buffer the frame was copied
// into (DisplayBackend::read_shown), what the screen will show.
using RegionReader = std::function<std::vector<platform::Image>(std::span<const platform::PixelRegion>)>;

class IntegrityMonitor {
 public:
  // Off (reads and checks nothing) when the scene has no safety regions, `enabled` is false, or
  // the frame is drawn at another size than the regions were measured at (off_reason() says why).
  IntegrityMonitor(const engine::Scene& scene, int width, int height, bool enabled = true, bool safe_path = true);

  bool on() const { return on_; }
  const std::string& off_reason() const { return off_reason_; }

  // After each frame was rendered (drawn or skipped). Reads back only the regions whose
  // pixels can differ from the ones read last: the renderer drew into them (Renderer::
  // take_written: the planned boxes, so a renderer that planned but did not draw is caught as a
  // freeze), or their expectation changed (a renderer that wrongly skipped is a freeze too); and
  // every region at least every kRefreshFrames calls. A needle is read through its window around
  // the expected angle, and whole when the window cannot decide, when it was read whole last
  // kRefreshFrames calls ago, and the first time. Returns this frame's faults.
  // `reader`: where the regions are read (nullptr: the renderer's resolved target).
  const std::vector<IntegrityFault>& check(engine::Renderer& renderer, const engine::BindingEvaluator& evaluator,
                                           const RegionReader* reader = nullptr);
  // Optional, before the frame is rendered with the evaluator's state check() will judge: tells
  // the renderer which boxes check() will read (Renderer::resolve_with_frame), so their MSAA
  // resolve joins the frame's own GPU flush instead of costing one more; and check() judges the
  // frame against the state named here, though the evaluator may hold the next frame's by then.
  // The verdicts are the same with or without it. `resolve` false: the state only (the regions are
  // read from a display's back buffer, which the frame's own resolve and copy fill).
  void prepare(engine::Renderer& renderer, const engine::BindingEvaluator& evaluator, bool resolve = true);

  std::uint64_t frames_checked() const { return frames_checked_; }
  std::uint64_t faults() const { return faults_; }
  std::uint64_t frozen_faults() const { return frozen_; }
  std::uint64_t safe_redraws() const { return safe_redraws_; }
  std::uint64_t regions_read() const { return regions_read_; }  // summed over the checks
  // Needle regions read whole (the first read, every kRefreshFrames calls, and whenever the
  // window could not decide), summed over the checks; the other needle reads were windows.
  std::uint64_t needles_read_whole() const { return needles_whole_; }
  // Every region is read again at least this often (calls): 15 frames, 0.5 s at 30 fps, the
  // heartbeat production safety renderers use, so a corrupted region nobody redraws is caught.
  static constexpr std::uint64_t kRefreshFrames = 15;
  const bridge::IntegrityTable& table() const { return table_; }

 private:
  void redraw_safe(engine::Renderer& renderer, std::size_t region, const engine::RegionExpectation& expected);
  platform::PixelRegion gl_box(const bridge::PixelRect& rect) const;  // GL window coordinates
  std::vector<bridge::PixelRect> read_rects(std::size_t region, std::uint64_t call) const;  // what check() reads
  void read_whole(std::size_t region);  // a needle read whole in this call
  std::size_t region_index(const std::string& name) const;

  const engine::Scene& scene_;
  const bridge::IntegrityTable& table_;
  bool on_ = false, safe_path_ = true;
  std::string off_reason_;
  int height_ = 0;
  std::vector<platform::PixelRegion> boxes_;  // each region's rect in GL window coordinates
  engine::ExpectedStates expectations_;
  std::vector<engine::RegionExpectation> expected_;  // this frame's, one per region
  bool prepared_ = false;  // expected_ was named by prepare() for the frame check() judges next
  std::vector<RegionMemory> memory_;
  std::vector<std::optional<std::uint64_t>> whole_due_;    // needles: the call they are next read whole in
  // Needles: the half width (pixels) their window allows for; it starts at kStartHalfWidth and
  // doubles whenever a window cut a needle that the whole rect then showed right.
  std::vector<int> half_width_;
  static constexpr int kStartHalfWidth = 4, kMaxHalfWidth = 64;
  std::vector<std::optional<std::uint64_t>> read_at_;       // the call a region was last read in
  std::vector<engine::RegionExpectation> read_expected_;   // its expectation then
  std::uint64_t frame_ = 0, regions_read_ = 0, needles_whole_ = 0;
  std::vector<IntegrityFault> frame_faults_;
  std::uint64_t frames_checked_ = 0, faults_ = 0, frozen_ = 0, safe_redraws_ = 0;
};

}  // namespace meter::runner
