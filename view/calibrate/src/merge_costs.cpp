#include "meter/calibrate/merge_costs.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>

#include "meter/calibrate/cost_samples.hpp"
#include "meter/engine/governor/cost_fit.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::calibrate {

namespace {

constexpr float kHalf = 0.025f;  // object half size in scene units (a few pixels at 640 x 480)

int add_node(engine::Scene& s, engine::Node n, int parent) {
  n.parent = parent;
  const int i = static_cast<int>(s.nodes.size());
  s.nodes.push_back(n);
  if (parent < 0) s.roots.push_back(i);
  else s.nodes[static_cast<std::size_t>(parent)].children.push_back(i);
  return i;
}

// One ribbon: two rows of v / 2 vertices, an indexed triangle list.
engine::Primitive ribbon(int v) {
  engine::Primitive p;
  p.material = 0;
  p.vertex_count = static_cast<std::uint32_t>(v);
  p.stride = 6;
  p.layout = {{bridge::AttributeSemantic::Position, -1, 3, 0}, {bridge::AttributeSemantic::Normal, -1, 3, 3}};
  const int half = v / 2;
  for (int i = 0; i < half; ++i)
    for (int r = 0; r < 2; ++r) {
      const float x = -kHalf + 2.0f * kHalf * float(i) / float(std::max(1, half - 1));
      p.vertices.insert(p.vertices.end(), {x, r ? kHalf : -kHalf, 0.0f, 0.0f, 0.0f, 1.0f});
    }
  for (int i = 0; i + 1 < half; ++i) {
    const auto a = static_cast<std::uint32_t>(2 * i);
    p.indices.insert(p.indices.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
  }
  p.bounds_min = glm::vec3(-kHalf, -kHalf, 0), p.bounds_max = glm::vec3(kHalf, kHalf, 0);
  return p;
}

// The slope of ms over x: the calibration's robust line fit (cost_fit.hpp), x in place of pixels.
double slope(const std::vector<engine::governor::CostSample>& points) { return engine::governor::fit_cost(points).a_ms_per_pixel; }

}  // namespace

engine::Scene split_model(int objects, int total_vertices) {
  if (objects < 1 || total_vertices / objects < 4 || (total_vertices / objects) % 2 != 0)
    throw std::invalid_argument("split model: " + std::to_string(total_vertices) + " vertices in " + std::to_string(objects) +
                                " objects, expected an even count >= 4 per object");
  const int v = total_vertices / objects;
  engine::Scene s;
  s.source_name = "split-" + std::to_string(objects);
  s.config.size = {640, 480};
  s.config.camera = "Camera";
  s.config.clear_color = {0.0, 0.0, 0.0, 1.0};
  engine::Material mat;
  mat.name = "Print";
  mat.shading = bridge::ShadingModel::Gouraud;  // per-vertex lighting: the per-vertex cost m is real
  mat.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  s.materials.push_back(mat);
  engine::Camera cam;
  cam.yfov = 0.8f;
  s.cameras.push_back(cam);
  engine::Light sun;
  sun.intensity = 3.0f;
  s.lights.push_back(sun);
  engine::Node c;
  c.name = "Camera", c.camera = 0, c.translation = glm::vec3(0, 0, 6);
  add_node(s, c, -1);
  engine::Node l;
  l.name = "Sun", l.light = 0, l.rotation = glm::angleAxis(-0.5f, glm::vec3(1, 0, 0));
  add_node(s, l, -1);
  engine::Node b;
  b.name = "Board";
  const int board = add_node(s, b, -1);
  const int cols = static_cast<int>(std::ceil(std::sqrt(double(objects) * 1.3)));
  const int rows = (objects + cols - 1) / cols;
  const float w = 6.0f, h = 4.2f, cw = w / float(cols), ch = h / float(rows);
  engine::MergedGroup g;
  g.name = "all";
  for (int o = 0; o < objects; ++o) {
    engine::Mesh m;
    m.name = "obj" + std::to_string(o);
    m.primitives.push_back(ribbon(v));
    engine::Node n;
    n.name = m.name;
    n.mesh = o;
    n.translation = glm::vec3(-w / 2 + cw * (float(o % cols) + 0.5f), -h / 2 + ch * (float(o / cols) + 0.5f), 0.0f);
    s.meshes.push_back(std::move(m));
    add_node(s, n, board);
    s.draws.push_back({static_cast<int>(s.nodes.size()) - 1, o, 0, 0});
    g.draws.push_back(o);
  }
  s.groups.push_back(g);
  engine::Animation a;
  a.name = "Wobble";
  engine::AnimSampler sm;
  sm.components = 4;
  sm.input = {0.0f, 1000.0f};
  const glm::quat q0 = glm::angleAxis(0.0f, glm::vec3(0, 0, 1)), q1 = glm::angleAxis(0.2f, glm::vec3(0, 0, 1));
  sm.output = {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w};
  a.samplers.push_back(sm);
  a.channels.push_back({0, board, engine::TargetPath::Rotation});
  a.end = 1000.0f;
  s.animations.push_back(a);
  bridge::MaterialFeatures f;
  f.shading = bridge::ShadingModel::Gouraud;
  f.lights.directional = 1;
  f.vertex_alpha = true;  // the same program draws both ways (constant alpha 1 when unmerged)
  engine::ProgramEntry pe;
  pe.program = shadergen::generate(f);
  s.programs.push_back(pe);
  return s;
}


MergeSample measure_merge(platform::GpuBackend& backend, int objects, int vertices, int frames) {
  const engine::Scene s = split_model(objects, vertices);
  std::array<std::unique_ptr<engine::Renderer>, 3> r;
  for (std::size_t k = 0; k < 3; ++k) {
    engine::RendererOptions o;
    o.msaa = 1;
    o.partial_redraw = false;
    o.static_layer = false;
    o.concatenate = k > 0;
    r[k] = std::make_unique<engine::Renderer>(backend, s, o);
  }
  std::array<std::vector<double>, 3> ms;
  engine::BindingOutputs out;
  out.node_visible.assign(s.nodes.size(), -1);
  out.emissive.assign(s.materials.size(), std::nullopt);
  out.base_color.assign(s.materials.size(), std::nullopt);
  for (int f = 0; f < frames + 2; ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      out.animation_time.assign(s.animations.size(), k == 2 ? 1.0 : 1.0 + f);  // [2]: nothing moves
      r[k]->apply(out);
      const auto t0 = std::chrono::steady_clock::now();
      r[k]->render(true, false);
      if (f >= 2) ms[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  return {objects, vertices, median(ms[0]), median(ms[1]), median(ms[2])};
}

std::vector<MergeSample> merge_sample_points(platform::GpuBackend& backend, int frames, std::ostream* progress) {
  std::vector<MergeSample> out;
  for (const auto& [n, v] : std::vector<std::pair<int, int>>{{10, 4000}, {100, 4000}, {400, 4000}, {100, 2000}, {100, 8000}}) {
    out.push_back(measure_merge(backend, n, v, frames));
    if (progress)
      *progress << "meter-calibrate: concatenation, " << n << " objects of " << v / n << " vertices: unmerged " << out.back().unmerged_ms
                << " ms, merged " << out.back().merged_moving_ms << " ms (moving), " << out.back().merged_static_ms << " ms (static)\n";
  }
  return out;
}

engine::governor::ConcatenationCosts fit_merge_costs(const std::vector<MergeSample>& samples) {
  std::map<int, int> per_v, per_n;
  for (const auto& s : samples) ++per_v[s.vertices], ++per_n[s.objects];
  auto most = [](const std::map<int, int>& m) {
    return std::max_element(m.begin(), m.end(), [](const auto& a, const auto& b) { return a.second < b.second; })->first;
  };
  if (per_n.size() < 2 || per_v.size() < 2)
    throw std::invalid_argument("concatenation costs: expected samples at two object counts and two vertex counts, got " +
                                std::to_string(per_n.size()) + " and " + std::to_string(per_v.size()));
  const int v0 = most(per_v), n0 = most(per_n);
  std::vector<engine::governor::CostSample> over_n, over_v;
  double s_sum = 0;
  for (const auto& s : samples) {
    if (s.vertices == v0) over_n.push_back({double(s.objects), s.unmerged_ms});
    if (s.objects == n0) over_v.push_back({double(s.vertices), s.unmerged_ms});
    s_sum += (s.merged_moving_ms - s.merged_static_ms) / double(s.vertices);
  }
  // fit_cost throws for fewer than two distinct x: one N at the common V, or one V at the common N.
  return {std::max(0.0, slope(over_n)), std::max(0.0, slope(over_v)), std::max(0.0, s_sum / double(samples.size()))};
}

}  // namespace meter::calibrate
