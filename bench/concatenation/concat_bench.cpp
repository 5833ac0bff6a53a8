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
// Part 3, the converter's break-even test: the costs measured as meter-calibrate measures them,
// the prediction of eq. 1-3 for the split model at every N and for the cluster's groups, side by
// side with the frames measured in this run (docs/concatenation.md, "Prediction against the
// measured frame").
//
// Output: CSV files (prediction.csv for part 3) + fit.txt in the output directory (default ./concat-bench), the plot is drawn
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

#include "meter/calibrate/merge_costs.hpp"
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


Scene split_model(int objects, int total_vertices = kTotalVertices) { return calibrate::split_model(objects, total_vertices); }

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

// Part 3: the converter's break-even test (merge_break_even.hpp) with the costs meter-calibrate
// measures (merge_costs.hpp, the same calls), against measured frames in this run: the split
// model at every N (every member moving: the test's worst case), and the cluster's groups against
// its unmerged / merged frame of part 2 (EGL).
void predictions_against_frames(const fs::path& out_dir, int frames, const Scene& cluster, const std::array<double, 2>& cluster_frame_ms) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  const ConcatenationCosts costs = calibrate::fit_merge_costs(calibrate::merge_sample_points(*backend, std::max(frames, 15), nullptr));
  std::printf("\npart 3: break-even test (EGL) with meter-calibrate's costs: oh = %.5f ms/draw, m = %.7f ms/vertex, s = %.7f ms/vertex\n",
              costs.draw_ms, costs.vertex_ms, costs.transform_ms);
  std::printf("%6s %5s | %9s %9s %9s | %9s %9s %9s | %-9s %-9s\n", "N", "v", "pred_bef", "pred_aft", "pred_save", "meas_bef", "meas_aft",
              "meas_save", "predicted", "measured");
  std::ofstream csv(out_dir / "prediction.csv");
  csv << "what,objects,vertices,predicted_before_ms,predicted_after_ms,predicted_saving_ms,measured_before_ms,measured_after_ms,measured_saving_ms\n";
  int agree = 0, total = 0;
  for (int n : {1, 2, 5, 10, 20, 50, 100, 250, 500, 1000}) {
    const MergePrediction p = predict_merge(costs, n, kTotalVertices, kTotalVertices);
    const calibrate::MergeSample m = calibrate::measure_merge(*backend, n, kTotalVertices, frames);
    const double save = m.unmerged_ms - m.merged_moving_ms;
    // The frame's constant part (clear, glFinish) is in the measured times, not in eq. 1-2: the
    // savings compare, and whether merging paid.
    std::printf("%6d %5d | %9.4f %9.4f %9.4f | %9.4f %9.4f %9.4f | %-9s %-9s\n", n, kTotalVertices / n, p.before_ms, p.after_ms,
                p.before_ms - p.after_ms, m.unmerged_ms, m.merged_moving_ms, save, p.pays() ? "pays" : "no", save > 0 ? "paid" : "no");
    csv << "split," << n << "," << kTotalVertices << "," << p.before_ms << "," << p.after_ms << "," << p.before_ms - p.after_ms << ","
        << m.unmerged_ms << "," << m.merged_moving_ms << "," << save << "\n";
    agree += p.pays() == (save > 0) ? 1 : 0;
    ++total;
  }
  std::printf("decision agrees with the measured frame at %d of %d split points\n", agree, total);
  const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/cluster/";
  ConvertOptions opt;
  opt.merge_costs = costs;
  const ConvertResult r = convert_gltf(dir + "cluster.glb", meter::config::load_scene_config(dir + "cluster.scene.json"), opt);
  std::printf("\ncluster with the break-even test (meter-convert --costs --report):\n%s", r.concat_report.c_str());
  // The cluster's merged groups (part 2's conversion, every allowed group), predicted together,
  // against part 2's measured frames.
  double predicted_save = 0.0;
  for (const MergePrediction& p : predict_groups(cluster, costs)) predicted_save += p.before_ms - p.after_ms;
  const double measured_save = cluster_frame_ms[0] - cluster_frame_ms[1];
  std::printf("cluster, all %zu groups merged: predicted saving %.4f ms, measured saving %.4f ms (unmerged %.3f ms, merged %.3f ms, part 2)\n",
              cluster.groups.size(), predicted_save, measured_save, cluster_frame_ms[0], cluster_frame_ms[1]);
  csv << "cluster,,,,," << predicted_save << "," << cluster_frame_ms[0] << "," << cluster_frame_ms[1] << "," << measured_save << "\n";
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

  std::array<double, 2> cluster_frame_ms{};  // EGL, unmerged and merged: part 3 compares them with the prediction
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
      if (kind == platform::BackendKind::Egl) cluster_frame_ms[k] = c + g;
    }
  }
  predictions_against_frames(out_dir, frames, cluster, cluster_frame_ms);
  std::printf("\nwritten: %s/{split.csv,fit.txt,cluster_draws.csv,cluster_frame.csv,prediction.csv}\n", out_dir.c_str());
  return 0;
}
