// Fuzzes the meter-costs/1 reader the way meter-view uses a cost file: parse it, match it to draw
// units, run the governor on it for a few frames. Checks: every rejection is std::invalid_argument
// naming the file; what was accepted writes back to a text that parses to the same file; every
// prediction is finite.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/engine/governor/cost_file.hpp"
#include "meter/engine/governor/governor.hpp"

namespace {

using namespace meter::engine::governor;

constexpr const char* kOrigin = "fuzz.costs.json";

void check_named(const std::invalid_argument& e) {
  if (!std::strstr(e.what(), kOrigin)) std::abort();
}

// The draw units the file describes: each entry's shadings in order of first appearance and as
// many LODs as its largest index (a file that leaves a combination out is stale for them).
std::vector<UnitLadder> ladders_of(const CostFile& f) {
  std::vector<UnitLadder> out;
  for (const UnitCostEntry& u : f.units) {
    UnitLadder l;
    l.name = u.name;
    int lods = 0;
    for (const LevelCost& c : u.levels) {
      if (std::find(l.shadings.begin(), l.shadings.end(), c.shading) == l.shadings.end()) l.shadings.push_back(c.shading);
      lods = std::max(lods, c.lod + 1);
    }
    l.lod_errors.assign(std::size_t(lods), 0.0f);
    l.lod_triangle_fractions.assign(std::size_t(lods), 1.0f);
    l.safety = u.levels.size() == 1;
    out.push_back(std::move(l));
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  CostFile file;
  try {
    file = parse_costs(text, kOrigin);
  } catch (const std::invalid_argument& e) {
    check_named(e);
    return 0;
  }
  if (parse_costs(write_costs(file), "rewritten") != file) std::abort();
  const std::vector<UnitLadder> ladders = ladders_of(file);
  if (ladders.size() > 4096 || std::any_of(ladders.begin(), ladders.end(), [](const UnitLadder& l) {
        return l.lod_errors.size() * l.shadings.size() > 4096;
      }))
    return 0;  // larger than any package; the greedy's cost is not what this target looks for
  CostModel model;
  try {
    model = bind_costs(file, ladders, kOrigin);
  } catch (const std::invalid_argument& e) {
    check_named(e);
    return 0;
  }
  Governor governor(model, {.target_ms = 16.7, .headroom = 0.05, .min_frames_between_changes = 0, .window = 8});
  for (int frame = 0; frame < 6; ++frame) {
    FrameLoad load;
    load.drawn = true;
    load.full_frame = frame % 3 == 0;
    for (std::size_t u = 0; u < model.units.size(); ++u) {
      const std::uint8_t b = size ? data[(u * 7 + std::size_t(frame)) % size] : 0;
      load.unit_pixels.push_back(double(b) * 1000.0 * (frame + 1));
      load.redrawn_pixels += load.unit_pixels.back();
    }
    const QualityChoice choice = governor.choose(load);
    if (!std::isfinite(governor.predicted_ms())) std::abort();
    governor.observe(load, choice, governor.predicted_ms() * 1.3 + 0.5);
    const GovernorState s = governor.state();
    if (!std::isfinite(s.scale.pixel) || !std::isfinite(s.scale.fixed)) std::abort();
  }
  return 0;
}
