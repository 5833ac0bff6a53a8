// Mesh concatenation benchmark (DENSO paper sec. 5.2, Fig. 11/13, Tables 2/3).
//
// Part 1, the paper's experiment: a 4,000-vertex model split into N objects (N x v = 4,000), all
// children of one node that moves every frame (so every member must be re-transformed: the
// paper's per-frame CPU transform, the worst case for concatenation). Each N is drawn unmerged
// (N draws) and merged (1 draw) from the same Scene with the same program, on both backends, and
// CPU time (bindings/pose/world + GL submission incl. the CPU member transforms) and GPU time
// (glFinish: llvmpipe executes the queued work there) are measured side by side per frame.
// Fits eq. (1)-(2) for oh, m, s and the break-even object count of eq. (3).
//
// Part 2, the cluster (scenes/cluster with cluster.scene.json): draw calls per function
// before/after (Table 2) and frame time before/after with the needles sweeping (Table 3).
//
// Output: CSV files + fit.txt in the output directory (default ./concat-bench), the plot is drawn
// by bench/concatenation/plot.py. Numbers are medians over the measured frames.
#include <algorithm>
#include <array>
#include <memory>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/shadergen/shadergen.hpp"
#include "bench_stats.hpp"

using meter::bench::median;

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

constexpr int kTotalVertices = 4000;
constexpr float kHalf = 0.025f;  // object half size in scene units (~107 pixels per unit)


// N ribbons (2 rows of v/2 vertices, indexed triangle lists) on a grid in front of the camera,
// children of "Board", which the animation "Wobble" rotates about Z (a little, every frame).
Scene split_model(int objects, int total_vertices = kTotalVertices) {
  const int v = total_vertices / objects;
  Scene s;
  s.source_name = "split-" + std::to_string(objects);
  s.config.size = {640, 480};
  s.config.camera = "Camera";
  s.config.clear_color = {0.0, 0.0, 0.0, 1.0};
  Material mat;
  mat.name = "Print";
  mat.shading = shadergen::ShadingModel::Gouraud;  // per-vertex lighting: the per-vertex cost m is real
  mat.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  s.materials.push_back(mat);
  Camera cam;
  cam.yfov = 0.8f;
  s.cameras.push_back(cam);
  Light sun;
  sun.intensity = 3.0f;
  s.lights.push_back(sun);
  auto add_node = [&](Node n, int parent) {
    n.parent = parent;
    const int i = static_cast<int>(s.nodes.size());
    s.nodes.push_back(n);
    if (parent < 0) s.roots.push_back(i);
    else s.nodes[static_cast<std::size_t>(parent)].children.push_back(i);
    return i;
  };
  Node c;
  c.name = "Camera", c.camera = 0, c.translation = glm::vec3(0, 0, 6);
  add_node(c, -1);
  Node l;
  l.name = "Sun", l.light = 0, l.rotation = glm::angleAxis(-0.5f, glm::vec3(1, 0, 0));
  add_node(l, -1);
  Node b;
  b.name = "Board";
  const int board = add_node(b, -1);
  const int cols = static_cast<int>(std::ceil(std::sqrt(double(objects) * 1.3)));
  const int rows = (objects + cols - 1) / cols;
  const float w = 6.0f, h = 4.2f, cw = w / float(cols), ch = h / float(rows);
  for (int o = 0; o < objects; ++o) {
    Primitive p;
    p.material = 0;
    p.vertex_count = static_cast<std::uint32_t>(v);
    p.stride = 6;
    p.layout = {{shadergen::AttributeSemantic::Position, -1, 3, 0}, {shadergen::AttributeSemantic::Normal, -1, 3, 3}};
    const int half = v / 2;
    for (int i = 0; i < half; ++i) {
      for (int r = 0; r < 2; ++r) {
        // Every object the same small size (~6x6 pixels) whatever N: the fill cost stays
        // negligible and equal, so the times show per-draw and per-vertex work (eqs. 1-2).
        const float x = -kHalf + 2.0f * kHalf * float(i) / float(std::max(1, half - 1));
        const float y = r ? kHalf : -kHalf;
        p.vertices.insert(p.vertices.end(), {x, y, 0.0f, 0.0f, 0.0f, 1.0f});
      }
    }
    for (int i = 0; i + 1 < half; ++i) {
      const auto a = static_cast<std::uint32_t>(2 * i);
      p.indices.insert(p.indices.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
    }
    p.bounds_min = glm::vec3(-kHalf, -kHalf, 0), p.bounds_max = glm::vec3(kHalf, kHalf, 0);
    Mesh m;
    m.name = "obj" + std::to_string(o);
    m.primitives.push_back(std::move(p));
    s.meshes.push_back(std::move(m));
    Node n;
    n.name = m.name;
    n.mesh = o;
    n.translation = glm::vec3(-w / 2 + cw * (float(o % cols) + 0.5f), -h / 2 + ch * (float(o / cols) + 0.5f), 0.0f);
    add_node(n, board);
    s.draws.push_back({static_cast<int>(s.nodes.size()) - 1, o, 0, 0});
  }
  Animation a;
  a.name = "Wobble";
  AnimSampler sm;
  sm.components = 4;
  sm.input = {0.0f, 1000.0f};
  const glm::quat q0 = glm::angleAxis(0.0f, glm::vec3(0, 0, 1)), q1 = glm::angleAxis(0.2f, glm::vec3(0, 0, 1));
  sm.output = {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w};
  a.samplers.push_back(sm);
  a.channels.push_back({0, board, TargetPath::Rotation});
  a.end = 1000.0f;
  s.animations.push_back(a);
  shadergen::MaterialFeatures f;
  f.shading = shadergen::ShadingModel::Gouraud;
  f.lights.directional = 1;
  f.vertex_alpha = true;  // the same program draws both ways (constant alpha 1 when unmerged)
  ProgramEntry pe;
  pe.program = shadergen::generate(f);
  s.programs.push_back(pe);
  MergedGroup g;
  g.name = "all";
  for (int d = 0; d < objects; ++d) g.draws.push_back(d);
  s.groups.push_back(g);
  return s;
}

struct Sample {
  double cpu = 0, gpu = 0;
};

// Median CPU / GPU ms per frame, unmerged (animation advancing), merged (advancing: every member
// re-transformed each frame) and merged static (nothing moves: no transforms). The three
// renderers take turns frame by frame so load from other processes hits all of them alike.
std::array<Sample, 3> measure(platform::GpuBackend& backend, const Scene& s, int frames) {
  std::array<std::unique_ptr<Renderer>, 3> r;
  for (int k = 0; k < 3; ++k) {
    RendererOptions o;
    o.msaa = 1;
    o.concatenate = k > 0;
    r[std::size_t(k)] = std::make_unique<Renderer>(backend, s, o);
  }
  std::array<std::vector<double>, 3> cpu, gpu;
  BindingOutputs out;
  out.node_visible.assign(s.nodes.size(), -1);
  out.emissive.assign(s.materials.size(), std::nullopt);
  out.base_color.assign(s.materials.size(), std::nullopt);
  for (int f = 0; f < frames + 5; ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      out.animation_time.assign(s.animations.size(), k == 2 ? 1.0 : 1.0 + f);
      r[k]->apply(out);
      const auto t = r[k]->render(true, false);
      if (f >= 5) cpu[k].push_back(t.update_ms + t.submit_ms), gpu[k].push_back(t.gpu_readback_ms);
    }
  }
  std::array<Sample, 3> res;
  for (std::size_t k = 0; k < 3; ++k) res[k] = {median(cpu[k]), median(gpu[k])};
  return res;
}

// Least squares y = a + b x.
std::pair<double, double> line_fit(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = double(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n, my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  const double b = sxx > 0 ? sxy / sxx : 0.0;
  return {my - b * mx, b};
}

std::string function_of(const std::string& node) {
  for (const char* p : {"Speedo", "Tacho"}) {
    if (node.rfind(p, 0) == 0) return p;
  }
  if (node.rfind("Fuel", 0) == 0 || node.rfind("Coolant", 0) == 0) return "Fuel+Temp";
  if (node.rfind("TT", 0) == 0) return "Telltales";
  return "Centre/panels";
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path out_dir = argc > 1 ? fs::path(argv[1]) : fs::path("concat-bench");
  const int frames = argc > 2 ? std::max(5, std::atoi(argv[2])) : 30;
  fs::create_directories(out_dir);
  const std::vector<int> splits = {1, 10, 100, 125, 200, 250, 500, 1000};
  std::ofstream csv(out_dir / "split.csv");
  csv << "backend,objects,vertices_per_object,mode,cpu_ms,gpu_ms,frame_ms\n";
  std::ofstream fit(out_dir / "fit.txt");
  std::printf("part 1: %d vertices split into N objects, median of %d frames, ms\n", kTotalVertices, frames);
  std::printf("%-7s %6s %5s | %9s %9s %9s | %9s %9s %9s | %9s %9s | %7s\n", "backend", "N", "v", "cpu_bef", "cpu_aft", "cpu_stat", "gpu_bef",
              "gpu_aft", "gpu_stat", "frame_bef", "frame_aft", "ratio");
  for (auto kind : {platform::BackendKind::Egl, platform::BackendKind::OSMesa}) {
    auto backend = platform::create_backend(kind);
    const std::string bname(platform::to_string(kind));
    std::vector<double> xn, cpu_before, gpu_before, frame_before, cpu_after, gpu_after, frame_after, cpu_static, gpu_static, frame_static;
    for (int n : splits) {
      const Scene s = split_model(n);
      const auto [before, after, still] = measure(*backend, s, frames);
      const int v = kTotalVertices / n;
      csv << bname << "," << n << "," << v << ",before," << before.cpu << "," << before.gpu << "," << before.cpu + before.gpu << "\n";
      csv << bname << "," << n << "," << v << ",after," << after.cpu << "," << after.gpu << "," << after.cpu + after.gpu << "\n";
      csv << bname << "," << n << "," << v << ",after_static," << still.cpu << "," << still.gpu << "," << still.cpu + still.gpu << "\n";
      std::printf("%-7s %6d %5d | %9.3f %9.3f %9.3f | %9.3f %9.3f %9.3f | %9.3f %9.3f | %7.2f\n", bname.c_str(), n, v, before.cpu, after.cpu, still.cpu,
                  before.gpu, after.gpu, still.gpu, before.cpu + before.gpu, after.cpu + after.gpu,
                  (before.cpu + before.gpu) / std::max(1e-9, after.cpu + after.gpu));
      std::fflush(stdout);
      xn.push_back(n);
      cpu_before.push_back(before.cpu), gpu_before.push_back(before.gpu), frame_before.push_back(before.cpu + before.gpu);
      cpu_after.push_back(after.cpu), gpu_after.push_back(after.gpu), frame_after.push_back(after.cpu + after.gpu);
      cpu_static.push_back(still.cpu), gpu_static.push_back(still.gpu), frame_static.push_back(still.cpu + still.gpu);
    }
    // m: the vertex sweep (100 objects, 2,000 / 4,000 / 8,000 vertices, unmerged): local slope in V
    // around V = 4,000 (far larger V per 6-pixel object turns into sub-pixel slivers, where llvmpipe's
    // cost per vertex is no longer constant).
    std::vector<double> xv, sweep_cpu, sweep_gpu, sweep_frame;
    for (int total : {2000, 4000, 8000}) {
      const auto r = measure(*backend, split_model(100, total), frames);
      xv.push_back(total), sweep_cpu.push_back(r[0].cpu), sweep_gpu.push_back(r[0].gpu), sweep_frame.push_back(r[0].cpu + r[0].gpu);
      csv << bname << ",100," << total / 100 << ",sweep_before," << r[0].cpu << "," << r[0].gpu << "," << r[0].cpu + r[0].gpu << "\n";
    }
    // The model with a per-frame constant c0 (clear, state, glFinish round trip) the paper's
    // equations leave out:
    //   eq. (1) before = c0 + (oh + m v) N = c0 + oh N + m V
    //   eq. (2) after  = c0 + oh + (s + m) (v + k) N; our merged array is an indexed triangle list
    //           (no strip-joining dummies), so k = 0 and after = c0 + oh + (s + m) V for every N;
    //   s = (after with every member moving - after with nothing moving) / V, measured directly;
    //   eq. (3) after < before  <=>  N > 1 + s V / oh   (paper, k = 3: (oh + s V) / (oh - 3 (s + m))).
    auto model = [&](const char* what, const std::vector<double>& bef, const std::vector<double>& aft, const std::vector<double>& stat,
                     const std::vector<double>& sweep) {
      const double m = line_fit(xv, sweep).second;
      const auto [a0, oh] = line_fit(xn, bef);
      const double c0 = a0 - m * kTotalVertices;
      double ds = 0;
      for (std::size_t i = 0; i < aft.size(); ++i) ds += aft[i] - stat[i];
      const double sv = ds / double(aft.size()) / kTotalVertices;
      const double breakeven = oh > 0 ? 1.0 + sv * kTotalVertices / oh : INFINITY;
      const double paper_k3 = (oh - 3 * (sv + m)) > 0 ? (oh + sv * kTotalVertices) / (oh - 3 * (sv + m)) : INFINITY;
      double rms_b = 0, rms_a = 0;
      for (std::size_t i = 0; i < xn.size(); ++i) {
        rms_b += std::pow(bef[i] - (c0 + oh * xn[i] + m * kTotalVertices), 2);
        rms_a += std::pow(aft[i] - (c0 + oh + (sv + m) * kTotalVertices), 2);
      }
      rms_b = std::sqrt(rms_b / double(xn.size())), rms_a = std::sqrt(rms_a / double(xn.size()));
      char line[600];
      std::snprintf(line, sizeof line,
                    "%s %s: c0 = %.4f ms, oh = %.5f ms/draw, m = %.7f ms/vertex, s = %.7f ms/vertex, break-even N = %.1f "
                    "(paper's eq. 3 with k=3: %.1f), rms residual before %.3f ms, after %.3f ms\n",
                    bname.c_str(), what, c0, oh, m, sv, breakeven, paper_k3, rms_b, rms_a);
      std::fputs(line, stdout);
      fit << bname << "," << what << "," << c0 << "," << oh << "," << m << "," << sv << "," << breakeven << "," << paper_k3 << "," << rms_b << ","
          << rms_a << "\n";
    };
    model("cpu", cpu_before, cpu_after, cpu_static, sweep_cpu);
    model("gpu", gpu_before, gpu_after, gpu_static, sweep_gpu);
    model("frame", frame_before, frame_after, frame_static, sweep_frame);
  }

  // ---- Part 2: the cluster.
  const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/cluster/";
  const Scene cluster = convert_gltf(dir + "cluster.glb", meter::config::load_scene_config(dir + "cluster.scene.json"), ConvertOptions{}).scene;
  std::map<std::string, std::pair<int, int>> per_function;  // before, after
  std::vector<int> grouped(cluster.draws.size(), -1);
  for (std::size_t g = 0; g < cluster.groups.size(); ++g) {
    for (int d : cluster.groups[g].draws) grouped[static_cast<std::size_t>(d)] = static_cast<int>(g);
  }
  for (std::size_t d = 0; d < cluster.draws.size(); ++d) {
    const std::string f = function_of(cluster.nodes[static_cast<std::size_t>(cluster.draws[d].node)].name);
    per_function[f].first++;
    if (grouped[d] < 0) per_function[f].second++;
  }
  for (const auto& g : cluster.groups) {
    std::string f = function_of(cluster.nodes[static_cast<std::size_t>(cluster.draws[static_cast<std::size_t>(g.draws[0])].node)].name);
    for (int d : g.draws) {
      if (function_of(cluster.nodes[static_cast<std::size_t>(cluster.draws[static_cast<std::size_t>(d)].node)].name) != f) f = "Shared (gauges)";
    }
    per_function[f].second++;
  }
  std::ofstream t2(out_dir / "cluster_draws.csv");
  t2 << "function,draws_before,draws_after\n";
  std::printf("\npart 2: cluster draw calls per function (Table 2)\n%-16s %8s %8s\n", "function", "before", "after");
  int tb = 0, ta = 0;
  for (const auto& [f, ba] : per_function) {
    std::printf("%-16s %8d %8d\n", f.c_str(), ba.first, ba.second);
    t2 << f << "," << ba.first << "," << ba.second << "\n";
    tb += ba.first, ta += ba.second;
  }
  std::printf("%-16s %8d %8d\n", "total", tb, ta);
  t2 << "total," << tb << "," << ta << "\n";

  std::ofstream t3(out_dir / "cluster_frame.csv");
  t3 << "backend,mode,cpu_ms,gpu_ms,frame_ms,draw_calls_per_frame,member_transforms_per_frame\n";
  std::printf("\ncluster frame time, 1280x480 MSAA 4, needles sweeping every frame, median of %d frames (Table 3)\n", frames);
  std::printf("%-7s %-8s %9s %9s %9s %7s %10s\n", "backend", "mode", "cpu_ms", "gpu_ms", "frame_ms", "draws", "transforms");
  const protocol::SignalId speed = protocol::find_signal("Vehicle.Speed")->id;
  const protocol::SignalId rpm = protocol::find_signal("Vehicle.Powertrain.CombustionEngine.Speed")->id;
  for (auto kind : {platform::BackendKind::Egl, platform::BackendKind::OSMesa}) {
    auto backend = platform::create_backend(kind);
    // Unmerged and merged take turns frame by frame (same load for both).
    std::array<std::unique_ptr<Renderer>, 2> r;
    std::array<std::unique_ptr<BindingEvaluator>, 2> ev;
    std::array<std::vector<double>, 2> cpu, gpu;
    std::array<RendererStats, 2> first{};
    for (std::size_t k = 0; k < 2; ++k) {
      RendererOptions o;
      o.concatenate = k == 1;
      r[k] = std::make_unique<Renderer>(*backend, cluster, o);
      ev[k] = std::make_unique<BindingEvaluator>(cluster);
    }
    protocol::SignalTable v;  // one table for the run; each frame sets both driven signals
    for (int f = 0; f < frames + 5; ++f) {
      v.set(speed, {double(f % 200), protocol::SignalStatus::Valid, ""});
      v.set(rpm, {double((f * 37) % 7000), protocol::SignalStatus::Valid, ""});
      for (std::size_t k = 0; k < 2; ++k) {
        ev[k]->update(v, true, -1.0);
        r[k]->apply(ev[k]->outputs());
        const auto t = r[k]->render(true, false);
        if (f == 4) first[k] = r[k]->stats();
        if (f >= 5) cpu[k].push_back(t.update_ms + t.submit_ms), gpu[k].push_back(t.gpu_readback_ms);
      }
    }
    for (std::size_t k = 0; k < 2; ++k) {
      const char* mode = k ? "merged" : "unmerged";
      const double draws = double(r[k]->stats().draw_calls - first[k].draw_calls) / frames;
      const double transforms = double(r[k]->stats().member_transforms - first[k].member_transforms) / frames;
      const double c = median(cpu[k]), g = median(gpu[k]);
      const std::string bn(platform::to_string(kind));
      std::printf("%-7s %-8s %9.3f %9.3f %9.3f %7.0f %10.1f\n", bn.c_str(), mode, c, g, c + g, draws, transforms);
      t3 << bn << "," << mode << "," << c << "," << g << "," << c + g << "," << draws << "," << transforms << "\n";
    }
  }
  std::printf("\nwritten: %s/{split.csv,fit.txt,cluster_draws.csv,cluster_frame.csv}\n", out_dir.c_str());
  return 0;
}
