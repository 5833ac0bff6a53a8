// Telltale regions: every visibility / emissive / colour binding, grouped by the signal they
// show. Each group is rendered lit (its nodes shown, its colours at their "on" values) and in each
// unlit look (nodes hidden; shown with the colours at "off"); the lamp pixels are where the lit
// render differs from an unlit one, and each look's signature is the mean colour over them.
#include <algorithm>
#include <cmath>
#include <map>

#include "scene_shots.hpp"

namespace meter::convert {
namespace {

// A lamp pixel changes by more than this between lit and unlit: well above MSAA edge noise
// (a few steps) and below any lamp colour against a dark window (>= 60 in the cluster).
constexpr int kLampStep = 32;
// How far a frame's mean over the lamp may drift from the look it shows (0..255, worst channel).
// Measured over both backends at MSAA 1, 2, 4 and 8 and the filter / precision / affine ladder
// points on scenes/cluster (IntegrityBounds, docs/integrity.md: largest drift 6.82, at MSAA 1,
// where the film filter the cluster is resolved with has no samples to spread a lamp's rim and no
// half-float samples to keep its light above white; 4.24 with 8-bit samples); 12 leaves a margin
// of 1.76 there (over five at every other point) while a lamp painted over or recoloured moves the mean by far more
// (the cluster's lit and unlit looks are about 100..220 apart; the painted-over lamp of the tests
// is 218 off).
constexpr double kTelltaleTolerance = 12.0;
// Lit and unlit looks closer than this cannot be told apart with that tolerance and margin.
constexpr double kMinSeparation = 3.0 * kTelltaleTolerance;

struct TelltaleGroup {
  std::string signal;
  std::vector<int> bindings;
};

std::array<double, 3> mean_over(const platform::Image& img, const bridge::PixelRect& r, const std::vector<std::uint8_t>& mask) {
  std::array<double, 3> s{0, 0, 0};
  std::size_t n = 0;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      if (!mask[std::size_t(y) * std::size_t(r.width) + std::size_t(x)]) continue;
      const auto* p = img.pixel(r.x + x, r.y + y);
      for (int c = 0; c < 3; ++c) s[std::size_t(c)] += p[c];
      ++n;
    }
  for (auto& v : s) v /= double(std::max<std::size_t>(n, 1));
  return s;
}

double channel_distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

// The group's bindings forced to one state on top of the no-signal outputs.
engine::BindingOutputs look(const Scene& scene, const engine::BindingOutputs& base, const TelltaleGroup& g, bool shown, bool lit) {
  auto o = base;
  for (int i : g.bindings) {
    const auto& b = scene.config.bindings[std::size_t(i)];
    if (b.kind == BindingKind::Visibility) {
      o.node_visible[std::size_t(scene.find_node(b.node))] = shown ? 1 : 0;
    } else {
      const auto& c = lit ? b.on : b.off;
      const auto m = std::size_t(scene.find_material(b.material));
      if (b.kind == BindingKind::Emissive) o.emissive[m] = glm::vec3(c[0], c[1], c[2]);
      else o.base_color[m] = glm::vec4(c[0], c[1], c[2], c[3]);
    }
  }
  return o;
}

// Keeps the lamp pixels whose eight neighbours are lamp pixels too (when any are): a lamp's rim
// is covered partly, by an amount that changes with the MSAA count (a lit rim pixel is 0..100 %
// lit), while its inside is drawn the same at every count.
void erode(std::vector<std::uint8_t>& mask, int w, int h) {
  std::vector<std::uint8_t> inner(mask.size(), 0);
  bool any = false;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      bool all = true;
      for (int dy = -1; dy <= 1 && all; ++dy)
        for (int dx = -1; dx <= 1 && all; ++dx) all = mask[std::size_t(y + dy) * std::size_t(w) + std::size_t(x + dx)] != 0;
      if (all) inner[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1, any = true;
    }
  if (any) mask = std::move(inner);
}

}  // namespace

void measure_telltales(const Scene& scene, SceneShots& shots, IntegrityMeasurement& out) {
  std::vector<TelltaleGroup> groups;
  std::map<std::string, std::size_t> by_signal;
  const auto& bindings = scene.config.bindings;
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const auto k = bindings[i].kind;
    if (k != BindingKind::Visibility && k != BindingKind::Emissive && k != BindingKind::Color) continue;
    auto [it, fresh] = by_signal.try_emplace(bindings[i].signal, groups.size());
    if (fresh) groups.push_back({bindings[i].signal, {}});
    groups[it->second].bindings.push_back(int(i));
  }
  const int w = shots.width(), h = shots.height();
  for (const TelltaleGroup& g : groups) {
    bridge::SafetyRegion r;
    r.kind = bridge::SafetyKind::Telltale;
    r.signal = g.signal;
    r.bindings = g.bindings;
    bool has_visibility = false, has_colour = false;
    for (int i : g.bindings) {
      const auto& b = bindings[std::size_t(i)];
      if (b.kind == BindingKind::Visibility) {
        if (r.node.empty()) r.node = b.node;
        has_visibility = true;
      } else {
        r.materials.push_back(b.material);
        has_colour = true;
      }
    }
    r.name = !r.node.empty() ? r.node : r.materials.front();
    const platform::Image lit = shots.shot(look(scene, shots.base(), g, true, true));
    std::vector<std::pair<std::string, platform::Image>> unlit;
    if (has_visibility) unlit.emplace_back("off", shots.shot(look(scene, shots.base(), g, false, false)));
    if (has_colour) unlit.emplace_back(has_visibility ? "unlit" : "off", shots.shot(look(scene, shots.base(), g, true, false)));
    std::vector<std::uint8_t> frame_mask(std::size_t(w) * std::size_t(h), 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (const auto& [name, img] : unlit)
          if (pixel_difference(lit, img, x, y) > kLampStep) frame_mask[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
    const auto box = mask_bounds(frame_mask, w, h);
    if (box.empty()) {
      out.skipped.push_back(r.name + " (telltale " + g.signal + "): lit and unlit renders do not differ at " +
                            std::to_string(w) + "x" + std::to_string(h) + " (off screen or covered)");
      continue;
    }
    r.rect = grow(box, 1, w, h);
    r.telltale.mask.assign(std::size_t(r.rect.width) * std::size_t(r.rect.height), 0);
    for (int y = 0; y < r.rect.height; ++y)
      for (int x = 0; x < r.rect.width; ++x)
        r.telltale.mask[std::size_t(y) * std::size_t(r.rect.width) + std::size_t(x)] =
            frame_mask[std::size_t(r.rect.y + y) * std::size_t(w) + std::size_t(r.rect.x + x)];
    erode(r.telltale.mask, r.rect.width, r.rect.height);
    r.telltale.looks.push_back({"on", true, mean_over(lit, r.rect, r.telltale.mask)});
    double separation = 1e9;
    for (const auto& [name, img] : unlit) {
      r.telltale.looks.push_back({name, false, mean_over(img, r.rect, r.telltale.mask)});
      separation = std::min(separation, channel_distance(r.telltale.looks.front().mean, r.telltale.looks.back().mean));
    }
    if (separation < kMinSeparation) {
      out.skipped.push_back(r.name + " (telltale " + g.signal + "): lit and unlit looks differ by only " +
                            std::to_string(separation) + " (at least " + std::to_string(kMinSeparation) + " needed)");
      continue;
    }
    r.telltale.tolerance = kTelltaleTolerance;
    out.table.regions.push_back(std::move(r));
  }
}

}  // namespace meter::convert
