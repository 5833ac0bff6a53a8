#include "meter/calibrate/calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <span>
#include <stdexcept>

#include "meter/calibrate/merge_costs.hpp"
#include "meter/calibrate/unit_isolation.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"

namespace meter::calibrate {
namespace gov = engine::governor;
namespace {

void check(const CalibrationOptions& o) {
  if (o.frames < 1) throw std::invalid_argument("calibration: frames must be >= 1, got " + std::to_string(o.frames));
  std::set<float> distinct;
  for (float s : o.node_scales) {
    if (!(s > 0.0f && s <= 1.0f)) throw std::invalid_argument("calibration: a node scale must be in (0, 1], got " + std::to_string(s));
    distinct.insert(s);
  }
  if (o.node_scales.empty() || o.node_scales.front() != 1.0f)
    throw std::invalid_argument("calibration: the first node scale must be 1 (the package as converted: its PSNR frames)");
  if (distinct.size() < 2) throw std::invalid_argument("calibration: at least two distinct node scales are needed to fit A and B");
}

// The package with every mesh node's scale times s: each unit covers fewer pixels, same levels.
engine::Scene scaled(const engine::Scene& scene, float s) {
  engine::Scene copy = scene;
  for (auto& n : copy.nodes)
    if (n.mesh >= 0) n.scale *= s;
  return copy;
}

gov::QualityChoice unit_at(std::size_t units, std::size_t u, const gov::UnitLevel& level) {
  gov::QualityChoice c;
  c.units.assign(units, gov::UnitLevel{});
  c.units[u] = level;
  return c;
}

double psnr_or_identical(const platform::Image& a, const platform::Image& b) {
  const double db = platform::psnr(a, b);
  return std::isfinite(db) ? std::min(db, kIdenticalPsnrDb) : kIdenticalPsnrDb;
}

// Full frames (partial redraw off) drawn with `outputs` at `choice`: the median wall time of
// `frames` render() calls (each ends in glFinish), after one untimed frame (a level's first use).
double timed(engine::Renderer& r, const engine::BindingOutputs& outputs, const gov::QualityChoice& choice, int frames) {
  r.apply(outputs);
  r.set_quality(choice);
  r.render(true, false);
  std::vector<double> ms;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    r.render(true, false);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(ms);
}

platform::Image drawn(engine::Renderer& r, const engine::BindingOutputs& outputs, const gov::QualityChoice& choice) {
  r.apply(outputs);
  r.set_quality(choice);
  r.render(true, true);
  return r.last_image();
}

// Every unit at the most expensive of its shadings not above `model` (none: its own), LOD 0.
gov::QualityChoice every_unit_at(std::span<const gov::UnitLadder> ladders, bridge::ShadingModel model) {
  gov::QualityChoice c;
  for (const auto& l : ladders) {
    gov::UnitLevel level;
    for (std::size_t sh = 0; sh < l.shadings.size() && !l.safety; ++sh)
      if (int(l.shadings[sh]) <= int(model)) {
        level.shading = static_cast<int>(sh);
        break;
      }
    c.units.push_back(level);
  }
  return c;
}

// Keio's ladder on the whole frame: pbr, blinn-phong, gouraud, flat, unlit, each drawn where it
// changes some unit's level from the rung above. The rungs take turns frame by frame (after one
// untimed frame each), so load from other processes hits them alike: their differences are small
// next to a busy machine's swings.
std::vector<ShadingRungSamples> shading_rungs(engine::Renderer& r, std::span<const gov::UnitLadder> ladders,
                                              const engine::BindingOutputs& state, const platform::Image& reference, int frames) {
  using bridge::ShadingModel;
  std::vector<ShadingRungSamples> out;
  std::vector<gov::QualityChoice> choices;
  for (ShadingModel model : {ShadingModel::PbrMetallicRoughness, ShadingModel::BlinnPhong, ShadingModel::Gouraud, ShadingModel::Flat,
                             ShadingModel::Unlit}) {
    const gov::QualityChoice c = every_unit_at(ladders, model);
    if (!choices.empty() && c.units == choices.back().units) continue;
    ShadingRungSamples s;
    s.model = model;
    if (!choices.empty()) s.psnr_db = psnr_or_identical(drawn(r, state, c), reference);
    out.push_back(s);
    choices.push_back(c);
  }
  r.apply(state);
  std::vector<std::vector<double>> ms(choices.size());
  for (int f = -1; f < frames; ++f)
    for (std::size_t k = 0; k < choices.size(); ++k) {
      r.set_quality(choices[k]);
      const auto t0 = std::chrono::steady_clock::now();
      r.render(true, false);
      if (f >= 0) ms[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  for (std::size_t k = 0; k < choices.size(); ++k) {
    out[k].frame_ms = median(ms[k]);
    std::vector<double> ratio;
    for (std::size_t f = 0; k > 0 && f < ms[k].size(); ++f) ratio.push_back(ms[k][f] / std::max(1e-9, ms[k - 1][f]));
    if (k > 0) out[k].vs_above = median(ratio);
  }
  return out;
}

}  // namespace

CostMeasurements measure_costs(platform::GpuBackend& backend, const engine::Scene& scene, const CalibrationOptions& options,
                               std::ostream* progress) {
  check(options);
  engine::RendererOptions ro;
  ro.msaa = options.msaa;
  ro.width = options.width, ro.height = options.height;
  ro.partial_redraw = false;  // every frame drawn in full: a unit's whole box counts
  ro.static_layer = false;
  std::vector<engine::Scene> scenes;
  for (float s : options.node_scales) scenes.push_back(scaled(scene, s));
  std::vector<std::unique_ptr<engine::Renderer>> rs;
  for (const auto& s : scenes) rs.push_back(std::make_unique<engine::Renderer>(backend, s, ro));

  CostMeasurements m;
  m.backend = std::string(backend.name());
  const auto ladders = rs.front()->draw_units();
  m.ladders.assign(ladders.begin(), ladders.end());
  const std::size_t units = ladders.size();
  const engine::BindingOutputs state = calibration_state(scene);
  const engine::BindingOutputs nothing = shown_alone(scene, state, {});
  const gov::QualityChoice full{};

  // The full frame's load at each node scale (each unit's box pixels), and the frame with no unit
  // drawn (without texts: the baseline a unit alone is measured over).
  std::vector<double> empty;
  for (auto& r : rs) {
    drawn(*r, state, full);
    m.unit_pixels.push_back(r->last_load().unit_pixels);
    if (m.unit_pixels.back().size() != units)
      throw std::invalid_argument("calibration: the renderer's frame load has " + std::to_string(m.unit_pixels.back().size()) +
                                  " unit pixel counts for " + std::to_string(units) + " draw units");
    empty.push_back(timed(*r, nothing, full, options.frames));
  }
  engine::BindingOutputs texts_only = nothing;
  texts_only.texts = state.texts;
  m.empty_ms = timed(*rs.front(), texts_only, full, options.frames);
  const platform::Image reference = drawn(*rs.front(), state, full);

  for (std::size_t u = 0; u < units; ++u) {
    const auto& ladder = ladders[u];
    const engine::BindingOutputs alone = shown_alone(scene, state, unit_nodes(scene, rs.front()->unit_draws(u)));
    bool off_screen = true;
    for (const auto& px : m.unit_pixels) off_screen = off_screen && px[u] == 0.0;
    for (std::size_t sh = 0; sh < ladder.shadings.size(); ++sh)
      for (std::size_t lod = 0; lod < ladder.lod_errors.size(); ++lod) {
        LevelSamples ls;
        ls.unit = static_cast<int>(u);
        ls.level = {static_cast<int>(sh), static_cast<int>(lod)};
        const auto choice = unit_at(units, u, ls.level);
        if (off_screen) {  // drawn nowhere in the calibration state: costs nothing, changes nothing
          for (std::size_t k = 0; k < rs.size(); ++k) ls.samples.push_back({0.0, 0.0});
          if (sh > 0 || lod > 0) ls.psnr_db = kIdenticalPsnrDb;
          m.levels.push_back(std::move(ls));
          continue;
        }
        for (std::size_t k = 0; k < rs.size(); ++k)
          // Below the empty frame is timing noise on a unit too small to time: 0.
          ls.samples.push_back({m.unit_pixels[k][u], std::max(0.0, timed(*rs[k], alone, choice, options.frames) - empty[k])});
        if (sh > 0 || lod > 0) ls.psnr_db = psnr_or_identical(drawn(*rs.front(), state, choice), reference);
        m.levels.push_back(std::move(ls));
      }
    if (progress) {
      *progress << "meter-calibrate: unit " << u + 1 << "/" << units << " " << ladder.name << ": " << ladder.shadings.size() << " shadings x "
                << ladder.lod_errors.size() << " LODs, " << m.unit_pixels.front()[u] << " px\n";
    }
  }

  // Rung 0 (the renderer's own samples, full size), then each cheaper rung the driver can draw.
  std::vector<gov::GlobalLevel> rungs{{options.msaa, 1.0f}};
  const int max_samples = backend.gl().info.max_samples;
  for (const auto& g : options.rungs)
    if (g.msaa <= max_samples && std::find(rungs.begin(), rungs.end(), g) == rungs.end()) rungs.push_back(g);
  for (const auto& g : rungs) {
    RungSamples rs_g;
    rs_g.level = g;
    const gov::QualityChoice choice{g, {}};
    for (auto& r : rs) rs_g.frame_ms.push_back(timed(*r, state, choice, options.frames));
    if (!(g == rungs.front())) rs_g.psnr_db = psnr_or_identical(drawn(*rs.front(), state, choice), reference);
    if (progress) *progress << "meter-calibrate: rung MSAA " << g.msaa << " scale " << g.scale << ": " << rs_g.frame_ms.front() << " ms\n";
    m.rungs.push_back(std::move(rs_g));
  }
  // Whole frames, taking turns: three times the frames of a point (the rungs differ by a few %).
  m.shading_rungs = shading_rungs(*rs.front(), ladders, state, reference, 3 * options.frames);
  for (auto& r : rs) r->set_quality(full);
  // The converter's break-even test's costs (merge_costs.hpp): more frames, the points are small.
  m.concatenation = fit_merge_costs(merge_sample_points(backend, std::max(options.frames, 15), progress));
  return m;
}

}  // namespace meter::calibrate
