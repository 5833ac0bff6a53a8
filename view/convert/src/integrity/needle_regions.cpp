// Needle regions: every animation binding whose animation rotates a node. Per rotated node:
//   1. render the needle hidden and at evenly spaced animation times; its pixels are where a
//      render differs from the hidden one, so its reach from the projected pivot is measured;
//   2. the annulus: inside that reach, at radii no other safety region (another needle's sweep, a
//      lamp, a readout box) reaches at any angle, so only this needle moves there;
//   3. its colour: the box holding the needle's core pixels in the annulus (those as far from the
//      dial as most of the needle is), refused when the dial without the needle has that colour too;
//   4. the angle table: the angle read back (integrity_check's needle_angle, the same reading the
//      checks use) at each sampled time, and the interpolation error at the midpoints.
#include <algorithm>
#include <cmath>

#include "meter/engine/integrity_check.hpp"
#include "scene_shots.hpp"

namespace meter::convert {
namespace {

// A needle pixel differs from the dial without it by more than this (a needle is drawn to be seen:
// the cluster's orange on the dark face differs by > 150); antialiased rims fall either side.
constexpr int kNeedleStep = 64;
// Channel margin around the colours of the needle's core pixels: covers the backends' and MSAA
// settings' shading differences (measured below 6 steps on the cluster). 16 took in the edges of
// the tachometer's red print once its samples kept light above white (half-float samples: the
// print's edges resolve to 255, 70-85, 50-60, the needle's core reaches 255, 81, 33); 10 leaves no
// dial pixel in any needle's box at either sample format.
constexpr int kColourMargin = 10;
// The colour box is learnt from the needle's core: pixels differing from the dial without the
// needle by at least this share of the needle's own contrast there (the 99th percentile of its
// pixels' differences). Its antialiased rim, and more so a film-filtered one, blends the needle's
// colour into the face; a box spanning those blends took in the dial's grey print and the
// tachometer's red zone at every radius, so the cluster's tachometer went unmonitored (and with
// the film filter the speedometer too). Measured on the cluster: a share of 0.75 left no dial
// pixel in any needle's box with 8-bit samples (box or film filter), and the tables' interpolation
// error fell from 0.303 to 0.195 deg (0.263 with the film filter). With half-float samples a
// needle's edge keeps red at 255 while its green falls, so 0.75 took edge pixels into the core
// and the box reached the red print; 0.8 (with the margin above) places all four needles at
// either sample format: interpolation error 0.309 deg with half floats, 0.208 with 8-bit samples.
constexpr double kNeedleCoreShare = 0.8;
// |angle read - angle expected| on a correct frame. Measured on scenes/cluster and minimal-gauge
// over both backends at MSAA 1, 2, 4 and 8 and the filter / precision / affine ladder points
// against tables measured on EGL at MSAA 4 (IntegrityBounds, docs/integrity.md, the cluster
// resolved with the film filter over half-float samples: at most 0.467 deg at MSAA 1, where there
// are no samples, 0.278 at MSAA 2, 0.148 otherwise; the tables' interpolation error at their
// midpoints 0.309 deg); 1.0 deg holds with a margin of two and still catches a needle 3 deg off.
constexpr double kNeedleTolerance = 1.0;

struct Needle {
  int binding = -1, animation = -1, node = -1;
  double pivot_x = 0, pivot_y = 0;
  double t0 = 0, t1 = 0;
  std::vector<std::uint8_t> swept;  // frame-size: pixels the needle covers at some sample
  std::vector<double> radii;        // of those pixels, from the pivot
  double angle_lo = 0, angle_hi = 0;  // swept screen angles of its centroid (unwrapped)
};

double value_at(const Binding& b, double t) {
  const double u = (t - b.time[0]) / (b.time[1] - b.time[0]);
  return b.input[0] + u * (b.input[1] - b.input[0]);
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = std::size_t(q * double(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

engine::BindingOutputs at(const engine::BindingOutputs& base, const Needle& n, double t, bool hidden) {
  auto o = base;
  o.animation_time[std::size_t(n.animation)] = t;
  if (hidden) o.node_visible[std::size_t(n.node)] = 0;
  return o;
}

double sample_time(const Needle& n, int k, int count) { return n.t0 + (n.t1 - n.t0) * k / double(count - 1); }

// Step 1: what the needle covers over its sweep.
Needle sweep(const Scene& scene, SceneShots& shots, int binding, int node, int samples) {
  const Binding& b = scene.config.bindings[std::size_t(binding)];
  Needle n;
  n.binding = binding, n.animation = scene.find_animation(b.animation), n.node = node;
  n.t0 = std::min(b.time[0], b.time[1]), n.t1 = std::max(b.time[0], b.time[1]);
  const int w = shots.width(), h = shots.height();
  const platform::Image hidden = shots.shot(at(shots.base(), n, n.t0, true));
  const glm::vec2 p = shots.project(node);
  n.pivot_x = p.x, n.pivot_y = p.y;
  n.swept.assign(std::size_t(w) * std::size_t(h), 0);
  bool swept = false;
  for (int k = 0; k < samples; ++k) {
    const platform::Image& img = shots.shot(at(shots.base(), n, sample_time(n, k, samples), false));
    double sx = 0, sy = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (pixel_difference(img, hidden, x, y) <= kNeedleStep) continue;
        const double dx = x + 0.5 - n.pivot_x, dy = y + 0.5 - n.pivot_y;
        n.swept[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
        n.radii.push_back(std::hypot(dx, dy));
        sx += dx, sy += dy;
      }
    if (sx == 0 && sy == 0) continue;
    const double a = std::atan2(sx, -sy) * 180.0 / M_PI;
    const double u = swept ? n.angle_hi + engine::wrap_degrees(a - n.angle_hi) : a;
    n.angle_lo = swept ? std::min(n.angle_lo, u) : u, n.angle_hi = swept ? std::max(n.angle_hi, u) : u;
    swept = true;
  }
  return n;
}

// The sector the reading looks in: the sweep plus kSectorMargin each side.
constexpr double kSectorMargin = 10.0;
double sector_center(const Needle& n) { return 0.5 * (n.angle_lo + n.angle_hi); }
double sector_half(const Needle& n) { return std::min(180.0, 0.5 * (n.angle_hi - n.angle_lo) + kSectorMargin); }
bool in_sector(const Needle& n, double dx, double dy) {
  return std::abs(engine::wrap_degrees(std::atan2(dx, -dy) * 180.0 / M_PI - sector_center(n))) <= sector_half(n);
}

// Step 2: the widest band of radii inside the needle's reach that no foreign pixel in its sector
// touches. Returns {0, 0} when none is wide enough.
std::pair<double, double> annulus(const Needle& n, const std::vector<std::uint8_t>& foreign, int w, int h,
                                  const std::vector<double>& dial_radii) {
  const double r_min = percentile(n.radii, 0.005), r_max = percentile(n.radii, 0.995);
  const double len = r_max - r_min;
  const double lo = r_min + 0.15 * len, hi = r_max - 0.02 * len;
  std::vector<double> blocked = {lo, hi};
  for (double r : dial_radii)
    if (r >= lo && r <= hi) blocked.push_back(r);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!foreign[std::size_t(y) * std::size_t(w) + std::size_t(x)]) continue;
      const double dx = x + 0.5 - n.pivot_x, dy = y + 0.5 - n.pivot_y, r = std::hypot(dx, dy);
      if (r >= lo && r <= hi && in_sector(n, dx, dy)) blocked.push_back(r);
    }
  std::sort(blocked.begin(), blocked.end());
  std::pair<double, double> best{0, 0};
  for (std::size_t i = 1; i < blocked.size(); ++i) {
    if (blocked[i] - blocked[i - 1] > best.second - best.first) best = {blocked[i - 1] + 1.0, blocked[i] - 1.0};
  }
  if (best.second - best.first < std::max(8.0, 0.25 * len)) return {0, 0};
  return best;
}

// The region for one annulus: rect, pivot, colour box learnt from the needle's pixels in the
// annulus over the sampled renders. `why` is set when the annulus is empty or the dial without
// the needle has too many pixels of that colour in it.
bridge::SafetyRegion needle_region(const Scene& scene, const Needle& n, std::pair<double, double> band,
                                   const platform::Image& hidden, const platform::Image& hidden_aliased,
                                   const std::vector<platform::Image>& imgs, int w, int h, std::string* why) {
  const Binding& b = scene.config.bindings[std::size_t(n.binding)];
  bridge::SafetyRegion r;
  r.name = r.node = scene.nodes[std::size_t(n.node)].name;
  r.kind = bridge::SafetyKind::Needle;
  r.signal = b.signal;
  r.bindings = {n.binding};
  const auto [r0, r1] = band;
  if (r1 <= r0) {
    *why = "other regions or its dial's print cross every radius it sweeps";
    return r;
  }
  const int x0 = std::max(0, int(std::floor(n.pivot_x - r1))), y0 = std::max(0, int(std::floor(n.pivot_y - r1)));
  const int x1 = std::min(w, int(std::ceil(n.pivot_x + r1)) + 1), y1 = std::min(h, int(std::ceil(n.pivot_y + r1)) + 1);
  r.rect = {x0, y0, x1 - x0, y1 - y0};
  auto& m = r.needle;
  m.animation = b.animation;
  m.pivot_x = n.pivot_x, m.pivot_y = n.pivot_y, m.r_min = r0, m.r_max = r1;
  m.sector_center_deg = sector_center(n), m.sector_half_deg = sector_half(n);
  // The needle's pixels in the annulus at every sampled time, with their difference from the dial,
  // gathered once; the core among them gives the colour box and the fewest pixels a frame shows.
  struct NeedlePixel {
    std::size_t shot;
    int x, y, difference;
  };
  std::vector<NeedlePixel> pixels;
  std::vector<double> differences;
  for (std::size_t i = 0; i < imgs.size(); ++i)
    for (int y = r.rect.y; y < r.rect.y + r.rect.height; ++y)
      for (int x = r.rect.x; x < r.rect.x + r.rect.width; ++x) {
        const double rr = std::hypot(x + 0.5 - n.pivot_x, y + 0.5 - n.pivot_y);
        const int d = pixel_difference(imgs[i], hidden, x, y);
        if (rr < r0 || rr > r1 || d <= kNeedleStep) continue;
        pixels.push_back({i, x, y, d});
        differences.push_back(d);
      }
  const double core = std::max(double(kNeedleStep), kNeedleCoreShare * percentile(differences, 0.99));
  std::array<std::vector<double>, 3> channel;
  std::vector<int> per_shot(imgs.size(), 0);
  for (const NeedlePixel& p : pixels) {
    if (p.difference < core) continue;
    for (std::size_t c = 0; c < 3; ++c) channel[c].push_back(imgs[p.shot].pixel(p.x, p.y)[c]);
    ++per_shot[p.shot];
  }
  const int fewest = per_shot.empty() ? 0 : *std::min_element(per_shot.begin(), per_shot.end());
  for (std::size_t c = 0; c < 3; ++c) {
    m.color_min[c] = std::max(0, int(percentile(channel[c], 0.01)) - kColourMargin);
    m.color_max[c] = std::min(255, int(percentile(channel[c], 0.99)) + kColourMargin);
  }
  m.min_pixels = std::max(1, fewest / 2);
  m.tolerance_deg = kNeedleTolerance;
  m.samples = {{n.t0, 0, 0}, {n.t1, 0, 0}};  // replaced by the measured table
  // The dial is judged at MSAA 4 and without antialiasing: a print edge that blends away at one
  // count is a solid colour at the other.
  int dial_matches = 0, aliased_matches = 0;
  engine::needle_angle(r, {hidden.rgba.data(), w, h, 0, 0, 0}, &dial_matches);
  engine::needle_angle(r, {hidden_aliased.rgba.data(), w, h, 0, 0, 0}, &aliased_matches);
  dial_matches = std::max(dial_matches, aliased_matches);
  // k stray pixels at an angle D from the needle's n move the centroid by about D k / (n + k):
  // one in a hundred of the fewest needle pixels across a 100 deg sweep is 1 deg, the tolerance.
  // So none is allowed; the caller blocks their radii and chooses the annulus again.
  if (dial_matches > 0) {
    *why = std::to_string(dial_matches) + " pixels of its dial in the annulus " + std::to_string(r0) + ".." +
           std::to_string(r1) + " px share the needle's colour";
  } else {
    why->clear();
  }
  return r;
}

// Radii (from the pivot) of the dial's pixels without the needle that pass the region's colour box.
std::vector<double> dial_match_radii(const bridge::SafetyRegion& r, const Needle& n, const platform::Image& hidden) {
  std::vector<double> out;
  const auto& m = r.needle;
  for (int y = r.rect.y; y < r.rect.y + r.rect.height; ++y)
    for (int x = r.rect.x; x < r.rect.x + r.rect.width; ++x) {
      const auto* p = hidden.pixel(x, y);
      bool in = true;
      for (std::size_t c = 0; c < 3; ++c) in = in && p[c] >= m.color_min[c] && p[c] <= m.color_max[c];
      const double dx = x + 0.5 - m.pivot_x, dy = y + 0.5 - m.pivot_y;
      if (in && in_sector(n, dx, dy)) out.push_back(std::hypot(dx, dy));
    }
  return out;
}

}  // namespace

void measure_needles(const Scene& scene, SceneShots& shots, SceneShots& aliased, const IntegrityOptions& options,
                     IntegrityMeasurement& out) {
  const int w = shots.width(), h = shots.height();
  const int samples = std::max(2, options.needle_samples);
  std::vector<Needle> needles;
  for (std::size_t i = 0; i < scene.config.bindings.size(); ++i) {
    const Binding& b = scene.config.bindings[i];
    if (b.kind != BindingKind::Animation) continue;
    const auto& anim = scene.animations[std::size_t(scene.find_animation(b.animation))];
    std::vector<int> nodes;
    for (const auto& ch : anim.channels)
      if (ch.path == TargetPath::Rotation && std::find(nodes.begin(), nodes.end(), ch.node) == nodes.end()) nodes.push_back(ch.node);
    if (!(std::abs(b.time[1] - b.time[0]) > 0.0)) continue;  // a constant pose: nothing moves
    for (int node : nodes) {
      Needle n = sweep(scene, shots, int(i), node, samples);
      if (n.radii.empty()) {
        out.skipped.push_back(scene.nodes[std::size_t(node)].name + " (needle " + b.signal + "): never visible at " +
                              std::to_string(w) + "x" + std::to_string(h));
        continue;
      }
      needles.push_back(std::move(n));
    }
  }
  // Pixels the other regions own: every lamp and readout box measured so far.
  std::vector<std::uint8_t> others(std::size_t(w) * std::size_t(h), 0);
  for (const auto& r : out.table.regions)
    for (int y = r.rect.y; y < r.rect.y + r.rect.height; ++y)
      for (int x = r.rect.x; x < r.rect.x + r.rect.width; ++x) others[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
  for (std::size_t k = 0; k < needles.size(); ++k) {
    const Needle& n = needles[k];
    const Binding& b = scene.config.bindings[std::size_t(n.binding)];
    const std::string name = scene.nodes[std::size_t(n.node)].name;
    auto foreign = others;
    for (std::size_t j = 0; j < needles.size(); ++j)
      if (j != k)
        for (std::size_t p = 0; p < foreign.size(); ++p) foreign[p] |= needles[j].swept[p];
    // Steps 2 and 3 together: a colour learnt in an annulus may match print of the dial there;
    // those radii are then blocked and the annulus chosen again (at most four times).
    const platform::Image hidden = shots.shot(at(shots.base(), n, n.t0, true));
    const platform::Image hidden_aliased = aliased.shot(at(aliased.base(), n, n.t0, true));
    std::vector<platform::Image> imgs;
    for (int s = 0; s < samples; ++s) imgs.push_back(shots.shot(at(shots.base(), n, sample_time(n, s, samples), false)));
    std::vector<double> dial_radii;
    bridge::SafetyRegion r;
    std::string why;
    for (int attempt = 0; attempt < 4; ++attempt) {
      r = needle_region(scene, n, annulus(n, foreign, w, h, dial_radii), hidden, hidden_aliased, imgs, w, h, &why);
      if (why.empty()) break;
      auto more = dial_match_radii(r, n, hidden);
      const auto more_aliased = dial_match_radii(r, n, hidden_aliased);
      more.insert(more.end(), more_aliased.begin(), more_aliased.end());
      if (more.empty()) break;
      dial_radii.insert(dial_radii.end(), more.begin(), more.end());
    }
    if (!why.empty()) {
      out.skipped.push_back(name + " (needle " + b.signal + "): " + why);
      continue;
    }
    auto& m = r.needle;
    // Step 4: the angle table, unwrapped, and its error at the midpoints.
    m.samples.clear();
    bool readable = true;
    for (int s = 0; s < samples && readable; ++s) {
      const auto a = engine::needle_angle(r, {imgs[std::size_t(s)].rgba.data(), w, h, 0, 0, 0});
      readable = a.has_value();
      if (!readable) break;
      const double t = sample_time(n, s, samples);
      const double angle = m.samples.empty() ? *a : m.samples.back().angle_deg + engine::wrap_degrees(*a - m.samples.back().angle_deg);
      m.samples.push_back({t, value_at(b, t), angle});
    }
    if (!readable) {
      out.skipped.push_back(name + " (needle " + b.signal + "): not readable at every sampled time");
      continue;
    }
    for (int s = 0; s + 1 < samples; ++s) {
      const double t = 0.5 * (sample_time(n, s, samples) + sample_time(n, s + 1, samples));
      const platform::Image& img = shots.shot(at(shots.base(), n, t, false));
      const auto a = engine::needle_angle(r, {img.rgba.data(), w, h, 0, 0, 0});
      if (!a) continue;
      const double e = std::abs(engine::wrap_degrees(*a - engine::expected_angle(m, t)));
      out.needle_interpolation_deg = std::max(out.needle_interpolation_deg, e);
    }
    out.table.regions.push_back(std::move(r));
  }
}

}  // namespace meter::convert
