// meter-bench (issue #9): what accuracy costs in time.
//
//   meter-bench fidelity [--backend egl|osmesa] [--out DIR] [--doc FILE] [--quality SPEC]
//     Renders the twelve feature scenes and the cluster in-process (convert_gltf + Renderer, the
//     product path: optimized programs, MSAA 4) and compares each with its Blender reference:
//     PSNR over the full frame, PSNR over the object pixels (object_mask of the reference against
//     its background colour, tolerance 8 levels) and SSIM. Writes DIR/fidelity.csv, the renders,
//     and docs/fidelity.md (the paper's Table 1 beside ours).
//
//   meter-bench accuracy [--backend egl|osmesa] [--out DIR] [--doc FILE] [--rounds N] [--frames N]
//     For each scene x quality-ladder point (quality.hpp): median and p99 frame time, measured
//     interleaved (round r draws K frames of every ladder point in turn, R rounds), and PSNR
//     against (a) the engine's maximum quality supersampled (2x size, MSAA 4, box-filtered down in
//     linear light) and (b) the Blender reference. Then fits the Keio cost model
//     time = A * object_pixels + B per shading model and LOD on the teapot of `specular` scaled
//     to several screen sizes. Writes DIR/accuracy.csv, DIR/keio.csv, cost-model.json (--model)
//     and docs/accuracy-vs-time.md; bench/fidelity/plot.py draws the PNG.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <thread>

#include <sys/utsname.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "meter/engine/bindings.hpp"
#include "meter/engine/converter.hpp"
#include "meter/engine/quality.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/protocol/catalog.hpp"

using namespace meter;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = METER_SOURCE_DIR;
constexpr int kMaskTolerance = 8;  // levels: JPEG/dither noise on the background is below it

struct SceneSpec {
  std::string name, glb, config, reference;  // reference: PNG or JPEG ("" = none)
  double paper_db = -1.0;                    // the paper's Table 1 (DENSO), -1 = no counterpart
  std::string paper_name;
};

std::vector<SceneSpec> all_scenes() {
  const std::vector<std::tuple<const char*, const char*, double>> features = {
      {"ambient", "Ambient", 38.68},   {"diffuse", "Diffuse", 37.13},     {"specular", "Specular", 45.64},
      {"shininess", "Shininess", 43.10}, {"emission", "Emission", 34.68},   {"bump", "Bump", 33.91},
      {"reflection", "Reflection", 31.28}, {"envmap2d", "Environment map (2D)", 38.54},
      {"skinning", "Skinning", 33.97}, {"morphing", "Morphing", 34.35},   {"spot", "Spot light", 38.11},
      {"omni", "Omni light", 39.02}};
  std::vector<SceneSpec> s;
  for (const auto& [n, paper, db] : features) {
    const fs::path d = kRoot / "scenes/features" / n;
    s.push_back({n, (d / (std::string(n) + ".glb")).string(), (d / "scene.json").string(), (d / "reference.png").string(), db, paper});
  }
  const fs::path c = kRoot / "scenes/cluster";
  s.push_back({"cluster", (c / "cluster.glb").string(), (c / "cluster.scene.json").string(),
               fs::exists(c / "preview-blender.png") ? (c / "preview-blender.png").string()
               : fs::exists(c / "preview-blender.jpg") ? (c / "preview-blender.jpg").string() : "",
               -1.0, ""});
  return s;
}

// The platform reads PNG only; the cluster's Blender preview is a JPEG: ImageMagick converts it.
platform::Image read_reference(const std::string& file, const fs::path& tmp_dir) {
  if (fs::path(file).extension() == ".png") return platform::read_png(file);
  const fs::path png = tmp_dir / (fs::path(file).stem().string() + ".ref.png");
  const std::string cmd = "convert '" + file + "' -depth 8 'PNG32:" + png.string() + "'";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error(file + ": ImageMagick 'convert' failed (package imagemagick)");
  return platform::read_png(png);
}

// The state each reference shows. Feature scenes: no signals (animations at config.time).
// Cluster: Blender's preview is frame 100 (speed needle at 100 km/h, every needle at its frame-100
// key or its end key), every telltale lit, no text (text is the engine's).
engine::BindingOutputs reference_state(const engine::Scene& scene, bool cluster) {
  std::map<int, engine::SignalValue> values;
  if (cluster) {
    for (const auto& b : scene.config.bindings) {
      const auto* info = protocol::find_signal(b.signal);
      if (!info || info->kind == protocol::SignalKind::Text) continue;
      engine::SignalValue v;
      v.status = protocol::SignalStatus::Valid;
      if (b.kind == engine::BindingKind::Visibility || b.kind == engine::BindingKind::Emissive || b.kind == engine::BindingKind::Color)
        v.value = b.has_input ? (b.invert ? b.input[0] : b.input[1]) : (b.invert ? b.threshold - 1.0 : b.threshold + 1.0);
      else
        v.value = b.input[0];
      values[info->id] = v;
    }
  }
  engine::BindingEvaluator ev(scene);
  ev.update([&](int id) -> const engine::SignalValue* {
    auto it = values.find(id);
    return it == values.end() ? nullptr : &it->second;
  }, true, -1.0);
  engine::BindingOutputs out = ev.outputs();
  if (cluster) {
    out.animation_time.assign(scene.animations.size(), 100.0 / 24.0);
    out.texts.clear();
  }
  return out;
}

struct Metrics {
  double full = 0, object = 0, ssim = 0, object_share = 0;
};

Metrics compare(const platform::Image& img, const platform::Image& ref) {
  const auto* bg = ref.pixel(0, 0);
  const platform::Mask mask = platform::object_mask(ref, {bg[0], bg[1], bg[2]}, kMaskTolerance);
  Metrics m;
  m.full = platform::psnr(img, ref);
  m.object = mask.count() ? platform::psnr_masked(img, ref, mask) : std::nan("");
  m.ssim = platform::ssim(img, ref);
  m.object_share = double(mask.count()) / (double(ref.width) * ref.height);
  return m;
}

// Where the difference to the reference is (docs/fidelity.md, "Where the difference is"):
//  - edges: pixels where the reference's luma changes by more than kEdgeLevels between
//    neighbours (silhouettes, ticks, numerals, texture detail); the share of the squared error
//    they carry, and the PSNR over the remaining pixels;
//  - blurred: PSNR after the same 5x5 binomial blur (sigma 1 px) of both images; what remains is
//    low-frequency shading (light, material, environment), not sharpness, anti-aliasing or JPEG;
//  - bias: mean signed difference per channel (engine - reference, levels): brighter / darker;
//  - worst cell of a 4 x 4 grid: PSNR there and its share of the frame's squared error.
constexpr int kEdgeLevels = 24;
struct Breakdown {
  double edge_share = 0, edge_error_share = 0, psnr_off_edges = 0, psnr_blurred = 0;
  double psnr_supersampled = 0;  // the engine drawn at 2x and box-filtered down (anti-aliasing bound)
  double bias[3] = {0, 0, 0};
  std::string worst_cell;
  double worst_cell_db = 0, worst_cell_share = 0;
};

double psnr_of_mse(double mse) { return mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : INFINITY; }

platform::Image blur5(const platform::Image& in) {
  static const int k[5] = {1, 4, 6, 4, 1};
  auto pass = [&](const platform::Image& src, int dx, int dy) {
    platform::Image out = src;
    for (int y = 0; y < src.height; ++y)
      for (int x = 0; x < src.width; ++x)
        for (int c = 0; c < 3; ++c) {
          int sum = 0;
          for (int i = -2; i <= 2; ++i) {
            const int xx = std::clamp(x + i * dx, 0, src.width - 1), yy = std::clamp(y + i * dy, 0, src.height - 1);
            sum += k[i + 2] * src.pixel(xx, yy)[c];
          }
          out.pixel(x, y)[c] = static_cast<std::uint8_t>((sum + 8) / 16);
        }
    return out;
  };
  return pass(pass(in, 1, 0), 0, 1);
}

Breakdown breakdown(const platform::Image& img, const platform::Image& ref) {
  Breakdown b;
  const int w = ref.width, h = ref.height;
  auto luma = [&](int x, int y) {
    const auto* p = ref.pixel(std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1));
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  };
  constexpr int kGrid = 4;
  double cell_se[kGrid][kGrid] = {};
  double total = 0, edge_se = 0, flat_se = 0;
  std::size_t edges = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double se = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(img.pixel(x, y)[c]) - double(ref.pixel(x, y)[c]);
        se += d * d;
        b.bias[c] += d;
      }
      se /= 3.0;
      total += se;
      const double l = luma(x, y);
      const bool edge = std::abs(luma(x + 1, y) - l) > kEdgeLevels || std::abs(luma(x - 1, y) - l) > kEdgeLevels ||
                        std::abs(luma(x, y + 1) - l) > kEdgeLevels || std::abs(luma(x, y - 1) - l) > kEdgeLevels;
      (edge ? edge_se : flat_se) += se;
      edges += edge;
      cell_se[y * kGrid / h][x * kGrid / w] += se;
    }
  const double n = double(w) * h;
  for (double& v : b.bias) v /= n;
  b.edge_share = double(edges) / n;
  b.edge_error_share = total > 0 ? edge_se / total : 0;
  b.psnr_off_edges = psnr_of_mse(flat_se / std::max(1.0, n - double(edges)));
  b.psnr_blurred = platform::psnr(blur5(img), blur5(ref));
  for (int gy = 0; gy < kGrid; ++gy)
    for (int gx = 0; gx < kGrid; ++gx)
      if (total > 0 && cell_se[gy][gx] / total > b.worst_cell_share) {
        b.worst_cell_share = cell_se[gy][gx] / total;
        b.worst_cell_db = psnr_of_mse(cell_se[gy][gx] / (n / (kGrid * kGrid)));
        b.worst_cell = "x " + std::to_string(gx * w / kGrid) + "-" + std::to_string((gx + 1) * w / kGrid) + ", y " +
                       std::to_string(gy * h / kGrid) + "-" + std::to_string((gy + 1) * h / kGrid);
      }
  return b;
}

platform::Image downsample2(const platform::Image& big);

engine::Scene convert(const SceneSpec& s, bool optimize) {
  // As shipped, concatenation groups included: fidelity is the product's (merged draws differ from
  // unmerged ones in at most 1e-4 of the pixels, view/engine/tests/concat_render_test.cpp).
  const engine::SceneConfig cfg = engine::load_scene_config(s.config);
  engine::ConvertOptions o;
  o.optimize = optimize;
  return engine::convert_gltf(s.glb, cfg, o).scene;
}

platform::Image render_once(platform::GpuBackend& backend, const engine::Scene& scene, const engine::BindingOutputs& state,
                            engine::RendererOptions o) {
  engine::Renderer r(backend, scene, o);
  r.apply(state);
  r.render(true, true);
  return r.last_image();
}

std::string machine_line(const platform::GpuBackend& backend) {
  utsname u{};
  uname(&u);
  std::string cpu = "?";
  std::ifstream ci("/proc/cpuinfo");
  for (std::string line; std::getline(ci, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return std::string(date) + "; " + cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores (shared), " +
         u.sysname + " " + u.release + "; " + backend.renderer_info();
}

std::string fmt(double v, int prec = 2) {
  if (std::isnan(v)) return "—";
  if (std::isinf(v)) return "identical";
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

// Why a scene is under target, and what fixes it: the interpretation of its measured breakdown
// (the numbers are printed from this run beside it), looked up by scene name; a scene under the
// bar without an entry is reported as "not analysed" so a new regression is never explained away.
std::string known_cause(const std::string& scene) {
  static const std::map<std::string, std::string> causes = {
      {"reflection", "The mirror shows the environment's grid lines and softbox edges: one mip-filtered lookup per pixel "
                     "(LOD from the reflection vector's screen footprint) where EEVEE averages 64 samples per pixel; the error "
                     "sits on those edges and falls with supersampling. Fix planned: anisotropic filtering of the footprint or "
                     "supersampling where the budget allows"},
      {"bump", "The hammered dimples' rims (normal-map detail) alias under MSAA 4, which does not multisample shading, while "
               "EEVEE averages 64 samples per pixel: the error sits on the rims and falls with supersampling. Toksvig-style "
               "roughness from the mip's normal length was tried and bought 0.06 dB (not kept). Fix planned: per-sample "
               "shading or supersampling of normal-mapped materials where the budget allows"},
      {"cluster", "Thin, high-contrast detail (ticks, numerals, needle and bezel outlines) carries almost all the error; the "
                  "reference is a JPEG (quality 85: the engine's own frame through the same JPEG scores 35.6 dB against "
                  "itself, a ceiling for any render) with EEVEE soft shadows (needle hubs) the engine does not draw. Fix "
                  "planned: a PNG Blender preview (scenes), supersampling or a wider resolve filter for the thin detail"},
  };
  auto it = causes.find(scene);
  return it == causes.end() ? "not analysed yet" : it->second;
}

// ---------------------------------------------------------------------------------------------
int run_fidelity(platform::BackendKind kind, const fs::path& out, const fs::path& doc, const std::string& quality) {
  fs::create_directories(out);
  const engine::QualitySettings q = engine::parse_quality(quality);
  auto backend = platform::create_backend(kind);
  std::ofstream csv(out / "fidelity.csv");
  csv << "scene,backend,psnr_full_db,psnr_object_db,ssim,object_share,paper_db,render_ms,error\n";
  struct Row {
    SceneSpec spec;
    Metrics m;
    std::string error;
    Breakdown where;
  };
  std::vector<Row> rows;
  for (const SceneSpec& s : all_scenes()) {
    Row row{s, {}, "", {}};
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (s.reference.empty()) throw std::runtime_error("no Blender preview in scenes/cluster");
      engine::Scene scene = convert(s, true);
      engine::RendererOptions o;  // the product's defaults (MSAA 4, concatenation on)
      // A ladder point (--quality) measures one setting against the product's defaults, e.g.
      // environment=off gives the engine's numbers from before it loaded environment maps.
      engine::apply_quality(scene, q);
      o.msaa = q.msaa.value_or(o.msaa);
      const platform::Image img = render_once(*backend, scene, reference_state(scene, s.name == "cluster"), o);
      platform::write_png(img, out / (s.name + ".engine.png"));
      const platform::Image ref = read_reference(s.reference, out);
      if (ref.width != img.width || ref.height != img.height)
        throw std::runtime_error(s.reference + ": " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                                 ", the engine renders " + std::to_string(img.width) + "x" + std::to_string(img.height));
      row.m = compare(img, ref);
      row.where = breakdown(img, ref);
      // Same scene at 2x size, box-filtered in linear light: how much of the gap is edge sampling.
      engine::RendererOptions big = o;
      big.width = img.width * 2, big.height = img.height * 2;
      row.where.psnr_supersampled =
          platform::psnr(downsample2(render_once(*backend, scene, reference_state(scene, s.name == "cluster"), big)), ref);
    } catch (const std::exception& e) {
      row.error = e.what();
      row.m = {std::nan(""), std::nan(""), std::nan(""), std::nan("")};
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::string err = row.error;
    std::replace(err.begin(), err.end(), ',', ';');
    std::replace(err.begin(), err.end(), '\n', ' ');
    csv << s.name << ',' << backend->name() << ',' << row.m.full << ',' << row.m.object << ',' << row.m.ssim << ','
        << row.m.object_share << ',' << s.paper_db << ',' << ms << ',' << err << '\n';
    std::printf("%-11s full %7s dB  object %7s dB  SSIM %6s  (paper %s)%s%s\n", s.name.c_str(), fmt(row.m.full).c_str(),
                fmt(row.m.object).c_str(), fmt(row.m.ssim, 4).c_str(), s.paper_db > 0 ? fmt(s.paper_db).c_str() : "—",
                row.error.empty() ? "" : "  ERROR: ", row.error.c_str());
    rows.push_back(std::move(row));
  }

  std::ostringstream md;
  md << "# Fidelity: the engine against the authoring tool (issue #9)\n\n"
     << "Generated by `meter-bench fidelity --backend " << backend->name()
     << (quality.empty() ? std::string() : " --quality " + quality) << "` — do not edit by hand; re-run it.\n\n"
     << "Machine and date: " << machine_line(*backend) << ".\n\n"
     << "Each scene is converted with `convert_gltf` (optimized programs and concatenation groups, the product path) and drawn in-process by the "
        "engine's `Renderer` (MSAA 4) in the state its reference shows, then compared with the Blender (EEVEE) render "
        "committed next to it (`scenes/features/<name>/reference.png`; cluster: `scenes/cluster/preview-blender.jpg`, "
        "frame 100, every telltale lit, no text). PSNR is computed in C++ (`meter::platform::psnr`, RGB, peak 255; "
        "cross-checked against ImageMagick `compare -metric PSNR` on a real render by `tests/fidelity`). "
        "*Object* PSNR counts only the pixels where the reference differs from its background colour by more than "
        << kMaskTolerance << " levels (`object_mask`); SSIM is the mean SSIM on luma. "
        "The paper's column is its Table 1 (DENSO, 640x480, one teapot per feature); 30 dB = acceptable, 40 dB = "
        "indistinguishable.\n\n"
     << "| scene | PSNR full (dB) | PSNR object (dB) | SSIM | object pixels | paper (dB) | verdict |\n|---|---|---|---|---|---|---|\n";
  int under = 0;
  for (const Row& r : rows) {
    const std::string paper = r.spec.paper_db > 0 ? fmt(r.spec.paper_db) + " (" + r.spec.paper_name + ")" : "— (not in the paper)";
    std::string verdict;
    if (!r.error.empty()) verdict = "not measured: " + r.error;
    else if (r.m.full < 30.0) verdict = "**under 30 dB**", ++under;
    else if (r.m.full < 35.0) verdict = "≥ 30 dB (under the 35 dB goal)";
    else verdict = r.m.full >= 40.0 ? "≥ 40 dB" : "≥ 35 dB";
    md << "| " << r.spec.name << " | " << fmt(r.m.full) << " | " << fmt(r.m.object) << " | " << fmt(r.m.ssim, 4) << " | "
       << (std::isnan(r.m.object_share) ? "—" : fmt(100.0 * r.m.object_share, 1) + " %") << " | " << paper << " | " << verdict << " |\n";
  }
  md << "\n## Where the difference is\n\n"
        "*Edges* are the pixels where the reference's luma changes by more than "
     << kEdgeLevels
     << " levels to a neighbour (silhouettes, ticks, numerals, texture detail). *Blurred* = PSNR after the same 5x5 "
        "binomial blur (σ ≈ 1 px) of both images: what is left is low-frequency shading, not sharpness, anti-aliasing or "
        "JPEG. *2x supersampled* = the engine drawn at twice the size (MSAA 4) and box-filtered down in linear light, "
        "against the same reference: how much better finer edge sampling alone gets. *Bias* = mean engine − reference per channel, in levels. *Worst cell* = the cell of a 4 x 4 grid with most "
        "of the squared error.\n\n"
     << "| scene | edge pixels | error on edges | PSNR off edges (dB) | PSNR blurred (dB) | PSNR 2x supersampled (dB) | bias R / G / B | worst cell (PSNR, share of error) |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    if (!r.error.empty()) continue;
    const Breakdown& b = r.where;
    md << "| " << r.spec.name << " | " << fmt(100.0 * b.edge_share, 1) << " % | " << fmt(100.0 * b.edge_error_share, 1) << " % | "
       << fmt(b.psnr_off_edges) << " | " << fmt(b.psnr_blurred) << " | " << fmt(b.psnr_supersampled) << " | " << fmt(b.bias[0], 1) << " / " << fmt(b.bias[1], 1) << " / "
       << fmt(b.bias[2], 1) << " | " << b.worst_cell << " (" << fmt(b.worst_cell_db) << " dB, " << fmt(100.0 * b.worst_cell_share, 0)
       << " %) |\n";
  }
  md << "\n## Scenes under target, reason and planned fix\n\n";
  bool any = false;
  for (const Row& r : rows) {
    const bool low_obj = r.error.empty() && r.m.object < 30.0;
    if (!r.error.empty() || r.m.full < 35.0 || low_obj) {
      any = true;
      md << "- **" << r.spec.name << "** (" << (r.error.empty() ? fmt(r.m.full) + " dB full, " + fmt(r.m.object) + " dB object" : "not measured")
         << "): ";
      if (r.error.empty())
        md << "measured: " << fmt(100.0 * r.where.edge_error_share, 0) << " % of the squared error on the " << fmt(100.0 * r.where.edge_share, 1)
           << " % edge pixels, " << fmt(r.where.psnr_off_edges) << " dB off them, " << fmt(r.where.psnr_supersampled)
           << " dB when drawn 2x supersampled. ";
      md << known_cause(r.spec.name) << ".\n";
    }
  }
  if (!any) md << "None: every scene is at or above 35 dB full-frame and 30 dB over object pixels.\n";
  md << "\n## What changed these numbers (2026-11-28, issue #9)\n\n"
        "Measured with this command before and after each change, EGL and OSMesa identical (full-frame dB; object dB in "
        "brackets):\n\n"
        "- **Environment maps** (the converter loads the image the scene extras name, `meter_environment`; "
        "docs/engine.md, \"Environment\"): reflection 19.02 (12.03) → 35.38 (28.47), envmap2d 31.85 (24.92) → "
        "42.33 (35.76); then the mirror's LOD from the reflection vector's screen footprint: reflection 37.75 (30.90). "
        "Of that, EEVEE's roughness-to-LOD mapping (sqrt(roughness) instead of roughness) is 1.41 dB and the footprint "
        "2.37 dB (a footprint twice as wide gains only 0.35 dB). "
        "`meter-bench fidelity --quality environment=off` reproduces the before column.\n"
        "- **Spot cone as Blender draws it** (smoothstep over (1 − cos(size/2)) · blend, docs/shaders.md): spot 29.25 "
        "(26.49) → 40.07 (37.48); cluster (two spot-lit dials) 27.02 → 27.44. For this scene's cone (inner 17°, outer "
        "20°) the glTF example curve gives 0.47 / 0.12 / 0.03 of full light at 18° / 19° / 19.5° off-axis where "
        "Blender gives 1.00 / 0.71 / 0.25: a dark ring 2.5° wide on the floor.\n"
        "- **Diffuse not scaled by (1 − F)** (Blender 3.x Principled): diffuse 40.40 → 41.96, specular 40.24 → "
        "41.40, shininess 39.37 → 40.49, morphing 40.59 → 41.93, spot 40.07 → 42.51, omni 39.82 → 41.92, ambient "
        "42.95 → 43.50, bump 34.78 → 35.24, skinning 37.96 → 38.32; emission and the environment scenes unchanged.\n"
        "\nFull-frame PSNR flatters small objects on black (the background matches exactly); the object column is the "
        "honest one and is the number to compare across scenes. The paper does not say which one its Table 1 is.\n\n"
     << "Files: `" << (out / "fidelity.csv").string() << "` (this table) and `<scene>.engine.png` (the renders).\n";
  fs::create_directories(doc.parent_path());
  std::ofstream(doc) << md.str();
  std::printf("%d scene(s) under 30 dB; wrote %s and %s\n", under, (out / "fidelity.csv").c_str(), doc.c_str());
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Accuracy vs time.

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = p * double(v.size() - 1);
  const auto lo = std::size_t(std::floor(pos));
  const auto hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (pos - double(lo)) * (v[hi] - v[lo]);
}

// 2x2 box filter in linear light (averaging sRGB codes darkens edges).
platform::Image downsample2(const platform::Image& big) {
  platform::Image out(big.width / 2, big.height / 2);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        double sum = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const double v = big.pixel(2 * x + dx, 2 * y + dy)[c] / 255.0;
            sum += c == 3 ? v : platform::srgb_to_linear(v);
          }
        const double avg = sum / 4.0;
        const double enc = c == 3 ? avg : platform::linear_to_srgb(avg);
        out.pixel(x, y)[c] = static_cast<std::uint8_t>(std::lround(std::clamp(enc, 0.0, 1.0) * 255.0));
      }
  return out;
}

struct Ladder {
  std::string name, spec;
  int scale = 1;  // 2: drawn at twice the size and box-filtered down (supersampling; not a quality.hpp setting)
};

std::vector<Ladder> ladder() {
  // Base = the maximum per-step quality (PBR, highp, trilinear, full mesh, MSAA 4); every other
  // point changes ONE setting, so each row says what that one step costs and gives.
  const std::string base = "shading=pbr,precision=highp,filter=trilinear,msaa=4";
  return {{"max (pbr msaa4)", base},
          {"blinn-phong", "shading=blinn-phong,precision=highp,filter=trilinear,msaa=4"},
          {"gouraud", "shading=gouraud,precision=highp,filter=trilinear,msaa=4"},
          {"flat", "shading=flat,precision=highp,filter=trilinear,msaa=4"},
          {"unlit", "shading=unlit,precision=highp,filter=trilinear,msaa=4"},
          // MSAA 8 where the driver has it (llvmpipe clamps to 4: the row then equals the base).
          {"msaa8", "shading=pbr,precision=highp,filter=trilinear,msaa=8"},
          {"msaa2", "shading=pbr,precision=highp,filter=trilinear,msaa=2"},
          {"msaa1", "shading=pbr,precision=highp,filter=trilinear,msaa=1"},
          {"mediump", "shading=pbr,precision=mediump,filter=trilinear,msaa=4"},
          {"anisotropic", "shading=pbr,precision=highp,filter=anisotropic,msaa=4"},
          {"bilinear", "shading=pbr,precision=highp,filter=bilinear,msaa=4"},
          {"nearest", "shading=pbr,precision=highp,filter=nearest,msaa=4"},
          // The EClay paper's trade: no perspective correction of varyings.
          {"affine", base + ",interpolation=affine"},
          {"lod0.5", base + ",lod=0.5"},
          {"lod0.25", base + ",lod=0.25"},
          // Only scenes with an environment map measure this point (elsewhere it changes nothing).
          {"no-env", base + ",environment=off"},
          // Supersampling on top of the maximum: the frame time is the 2x draw (the downsample, a
          // GPU blit on a target, is done on the CPU here and not timed).
          {"ss2x", base, 2},
          {"cheapest", "shading=unlit,precision=mediump,filter=nearest,msaa=1,lod=0.25"}};
}

struct Point {
  std::string scene, setting, spec;
  double median_ms = 0, p99_ms = 0, db_ss = 0, db_ref = 0;
  std::size_t samples = 0;
};

// Least squares y = A x + B, with R^2.
struct Fit {
  double a = 0, b = 0, r2 = 0;
  std::size_t n = 0;
};
Fit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  Fit f;
  f.n = x.size();
  if (x.size() < 2) return f;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= double(x.size()), my /= double(y.size());
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my), syy += (y[i] - my) * (y[i] - my);
  }
  f.a = sxx > 0 ? sxy / sxx : 0.0;
  f.b = my - f.a * mx;
  double ssr = 0;
  for (std::size_t i = 0; i < x.size(); ++i) ssr += std::pow(y[i] - (f.a * x[i] + f.b), 2);
  f.r2 = syy > 0 ? 1.0 - ssr / syy : 0.0;
  return f;
}

// Interleaved timing: every renderer draws `frames` frames per round, in turn, for `rounds` rounds.
std::vector<std::vector<double>> time_interleaved(std::vector<std::unique_ptr<engine::Renderer>>& rs, int rounds, int frames) {
  std::vector<std::vector<double>> t(rs.size());
  for (auto& r : rs) r->render(true, false);  // warm-up: first-use shader compile, mip generation
  for (int round = 0; round < rounds; ++round)
    for (std::size_t i = 0; i < rs.size(); ++i)
      for (int f = 0; f < frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        rs[i]->render(true, false);  // draw + glFinish: llvmpipe runs the frame inside
        t[i].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
  return t;
}

std::size_t count_non_background(const platform::Image& img) {
  const auto* bg = img.pixel(0, 0);
  return platform::object_mask(img, {bg[0], bg[1], bg[2]}, 0).count();
}

int run_accuracy(platform::BackendKind kind, const fs::path& out, const fs::path& doc, const fs::path& model_file, int rounds,
                 int frames, const std::vector<std::string>& only) {
  fs::create_directories(out);
  auto backend = platform::create_backend(kind);
  const auto t_start = std::chrono::steady_clock::now();
  std::vector<Point> points;
  std::ofstream csv(out / "accuracy.csv");
  csv << "scene,setting,spec,median_ms,p99_ms,samples,psnr_vs_supersampled_db,psnr_vs_blender_db\n";
  // A rung the driver cannot draw is left out and said so, not measured as a copy of the base
  // (llvmpipe's GL_MAX_SAMPLES is 4, so MSAA 8 would silently be MSAA 4).
  std::vector<Ladder> steps;
  std::vector<std::string> left_out;
  for (const Ladder& l : ladder()) {
    const auto q = engine::parse_quality(l.spec);
    if (q.msaa && *q.msaa > backend->gl().info.max_samples) {
      left_out.push_back("`" + l.name + "` (the driver draws at most " + std::to_string(backend->gl().info.max_samples) +
                         " samples)");
      std::printf("ladder point %s left out\n", left_out.back().c_str());
      continue;
    }
    steps.push_back(l);
  }
  std::vector<std::string> skipped;
  for (const SceneSpec& s : all_scenes()) {
    if (!only.empty() && std::find(only.begin(), only.end(), s.name) == only.end()) continue;
    engine::Scene base;
    platform::Image ref, ss;
    engine::BindingOutputs state;
    try {
      // optimize = false: regenerated ladder programs are not constant-folded (quality.hpp), so the
      // base is unfolded too and only the ladder setting differs between rows.
      base = convert(s, false);
      state = reference_state(base, s.name == "cluster");
      if (!s.reference.empty()) ref = read_reference(s.reference, out);
      engine::RendererOptions big;
      big.width = base.config.size[0] * 2, big.height = base.config.size[1] * 2, big.msaa = 4;
      ss = downsample2(render_once(*backend, base, state, big));
    } catch (const std::exception& e) {
      skipped.push_back(s.name + ": " + e.what());
      std::printf("%-11s skipped: %s\n", s.name.c_str(), e.what());
      continue;
    }
    std::vector<std::unique_ptr<engine::Renderer>> rs;
    std::vector<engine::Scene> scenes(steps.size());
    std::vector<Point> ps;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      scenes[i] = base;
      const engine::QualitySettings q = engine::parse_quality(steps[i].spec);
      try {
        const engine::QualityReport rep = engine::apply_quality(scenes[i], q);
        if (q.environment == false && !rep.environment_dropped) continue;  // no map: the base again
      } catch (const std::exception& e) {
        skipped.push_back(s.name + " / " + steps[i].name + ": " + e.what());
        std::printf("%-11s %-16s skipped: %s\n", s.name.c_str(), steps[i].name.c_str(), e.what());
        continue;
      }
      engine::RendererOptions o;
      o.msaa = q.msaa.value_or(4);
      if (steps[i].scale > 1) o.width = base.config.size[0] * steps[i].scale, o.height = base.config.size[1] * steps[i].scale;
      rs.push_back(std::make_unique<engine::Renderer>(*backend, scenes[i], o));
      rs.back()->apply(state);
      rs.back()->render(true, true);
      const platform::Image img = steps[i].scale == 2 ? downsample2(rs.back()->last_image()) : rs.back()->last_image();
      Point p{s.name, steps[i].name, steps[i].spec, 0, 0, platform::psnr(img, ss),
              (!ref.empty() && ref.width == img.width && ref.height == img.height) ? platform::psnr(img, ref) : std::nan(""), 0};
      ps.push_back(p);
    }
    const auto times = time_interleaved(rs, rounds, frames);
    for (std::size_t i = 0; i < ps.size(); ++i) {
      ps[i].median_ms = percentile(times[i], 0.5), ps[i].p99_ms = percentile(times[i], 0.99), ps[i].samples = times[i].size();
      csv << ps[i].scene << ',' << ps[i].setting << ",\"" << ps[i].spec << "\"," << ps[i].median_ms << ',' << ps[i].p99_ms << ','
          << ps[i].samples << ',' << ps[i].db_ss << ',' << ps[i].db_ref << '\n';
      std::printf("%-11s %-16s %8.2f ms (p99 %8.2f)  %7s dB vs supersampled  %7s dB vs Blender\n", s.name.c_str(),
                  ps[i].setting.c_str(), ps[i].median_ms, ps[i].p99_ms, fmt(ps[i].db_ss).c_str(), fmt(ps[i].db_ref).c_str());
      points.push_back(ps[i]);
    }
    std::fflush(stdout);
  }
  csv.close();

  // Keio cost model: the `specular` teapot scaled so it covers different screen areas; per shading
  // model and LOD, time = A * object_pixels + B over the sizes (MSAA 1, so a pixel is shaded once).
  const SceneSpec teapot = all_scenes()[2];
  const engine::Scene tbase = convert(teapot, false);
  const auto tstate = reference_state(tbase, false);
  const std::vector<double> scales = {0.3, 0.5, 0.7, 0.85, 1.0, 1.2};
  const std::vector<std::string> shadings = {"unlit", "flat", "gouraud", "blinn-phong", "pbr"};
  const std::vector<float> lods = {1.0f, 0.5f, 0.25f};
  std::ofstream kcsv(out / "keio.csv");
  kcsv << "shading,lod,scale,object_pixels,median_ms\n";
  nlohmann::json model;
  model["format"] = "meter-cost-model/1";
  model["model"] = "frame_ms = A_ms_per_pixel * object_pixels + B_ms";
  model["backend"] = std::string(backend->name());
  model["renderer"] = backend->renderer_info();
  model["scene"] = "scenes/features/specular (teapot, scaled), 640x480, MSAA 1";
  model["fits"] = nlohmann::json::array();
  std::ostringstream keio_md;
  keio_md << "| shading | LOD | A (ns / pixel) | B (ms) | R² | points |\n|---|---|---|---|---|---|\n";
  for (const auto& sh : shadings)
    for (float lod : lods) {
      std::vector<engine::Scene> sc(scales.size());
      std::vector<std::unique_ptr<engine::Renderer>> rs;
      std::vector<double> px;
      for (std::size_t k = 0; k < scales.size(); ++k) {
        sc[k] = tbase;
        for (auto& n : sc[k].nodes)
          if (n.mesh >= 0) n.scale *= float(scales[k]);
        engine::QualitySettings q = engine::parse_quality("shading=" + sh);
        if (lod < 1.0f) q.global.lod = lod;
        engine::apply_quality(sc[k], q);
        engine::RendererOptions o;
        o.msaa = 1;
        rs.push_back(std::make_unique<engine::Renderer>(*backend, sc[k], o));
        rs.back()->apply(tstate);
        rs.back()->render(true, true);
        px.push_back(double(count_non_background(rs.back()->last_image())));
      }
      const auto times = time_interleaved(rs, rounds, frames);
      std::vector<double> med;
      for (std::size_t k = 0; k < scales.size(); ++k) {
        med.push_back(percentile(times[k], 0.5));
        kcsv << sh << ',' << lod << ',' << scales[k] << ',' << px[k] << ',' << med.back() << '\n';
      }
      const Fit f = fit_line(px, med);
      model["fits"].push_back({{"shading", sh}, {"lod", lod}, {"A_ms_per_pixel", f.a}, {"B_ms", f.b}, {"r2", f.r2}, {"points", f.n}});
      keio_md << "| " << sh << " | " << lod << " | " << fmt(f.a * 1e6, 1) << " | " << fmt(f.b, 3) << " | " << fmt(f.r2, 3) << " | " << f.n << " |\n";
      std::printf("keio %-12s lod %.2f  A = %.1f ns/px  B = %.3f ms  R^2 = %.3f\n", sh.c_str(), double(lod), f.a * 1e6, f.b, f.r2);
    }
  fs::create_directories(model_file.parent_path());
  std::ofstream(model_file) << model.dump(2) << '\n';

  // Plot (python3-matplotlib); a missing matplotlib is reported, not fatal.
  const fs::path plot = kRoot / "bench/fidelity/plot.py";
  const fs::path png = doc.parent_path() / "images/accuracy-vs-time.png";
  fs::create_directories(png.parent_path());
  const std::string cmd = "/usr/bin/python3 '" + plot.string() + "' '" + (out / "accuracy.csv").string() + "' '" + png.string() + "'";
  const bool plotted = std::system(cmd.c_str()) == 0;

  // The doc: per ladder step, averaged over scenes, what it saves in ms and loses in dB.
  struct Delta {
    std::vector<double> ms_saved, db, base_db;  // per scene that measured the setting
    std::vector<double> db_ref_change;          // dB against Blender: this setting - the base
    std::vector<double> base_ms;
  };
  std::map<std::string, Delta> delta;
  std::map<std::string, const Point*> base_of;
  for (const Point& p : points)
    if (p.setting == steps[0].name) base_of[p.scene] = &p;
  for (const Point& p : points) {
    const Point* b = base_of[p.scene];
    if (!b || p.setting == b->setting) continue;
    delta[p.setting].ms_saved.push_back(b->median_ms - p.median_ms);
    // ss2x IS the supersampled image (identical, +inf dB): it has no "vs supersampled" number.
    if (!std::isinf(p.db_ss) && !std::isinf(b->db_ss)) {
      delta[p.setting].db.push_back(p.db_ss);
      delta[p.setting].base_db.push_back(b->db_ss);
    }
    delta[p.setting].base_ms.push_back(b->median_ms);
    if (!std::isnan(p.db_ref) && !std::isnan(b->db_ref)) delta[p.setting].db_ref_change.push_back(p.db_ref - b->db_ref);
  }
  const double minutes = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() / 60.0;
  std::ostringstream md;
  md << "# Accuracy vs time: what each quality step costs (issue #9)\n\n"
     << "Generated by `meter-bench accuracy --backend " << backend->name() << " --rounds " << rounds << " --frames " << frames
     << "` — re-run it rather than editing. Run time " << fmt(minutes, 1) << " min.\n\n"
     << "Machine and date: " << machine_line(*backend) << ". llvmpipe renders on the CPU, so these milliseconds are "
        "CPU time on a 2-core machine shared with other jobs: the ratios between rows, measured interleaved in one run, "
        "are the result, not the absolute values; a GPU target needs its own run.\n\n"
     << "Method: each scene is converted once (optimize off, so regenerated programs and the base differ only in the "
        "ladder setting) and every ladder point gets its own Renderer; round r draws " << frames << " frames of every point in turn, "
     << rounds << " rounds (" << rounds * frames << " frames per point; few, to keep the command to a few minutes — p99 over so few "
        "frames is close to the maximum). Frame time = `Renderer::render(force)` wall time, which includes glFinish (llvmpipe "
        "executes the frame there). PSNR (a) against the engine's maximum quality supersampled (PBR, highp, trilinear, MSAA 4 "
        "drawn at 2x size and box-filtered to 1x in linear light) and (b) against the Blender reference. `no-env` (the "
        "environment map dropped, `environment=off`) runs only on the scenes that name one; `ss2x` is the maximum drawn at "
        "2x size (timed without the downsample, a GPU blit on a target) and is by construction identical to (a).\n\n"
     << "![frame time vs PSNR, Pareto front marked](images/accuracy-vs-time.png)\n\n";
  for (const auto& l : left_out) md << "Left out on this backend: " << l << ".\n\n";
  if (!plotted) md << "(The plot was not drawn: `" << cmd << "` failed; install python3-matplotlib, see scripts/install-deps.)\n\n";
  md << "## What each step buys, averaged over the scenes\n\n"
     << "Each row changes one setting from the maximum (PBR, highp, trilinear, full mesh, MSAA 4). *ms saved* = base median − "
        "this median (negative = slower); *dB* = PSNR of this setting against the supersampled maximum.\n\n"
     << "| step | scenes | ms saved per frame (mean over scenes) | PSNR vs supersampled (mean dB) | dB vs Blender, change (mean) | in plain words |\n|---|---|---|---|---|---|\n";
  auto mean = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m += x;
    return v.empty() ? 0.0 : m / double(v.size());
  };
  for (const auto& st : steps) {
    auto it = delta.find(st.name);
    if (it == delta.end()) continue;
    // The base is averaged over the same scenes as the step (no-env only runs on scenes with a map).
    const double dms = mean(it->second.ms_saved), db = mean(it->second.db), base_db = mean(it->second.base_db);
    const double lost = base_db - db;
    std::string words;
    if (it->second.db.empty()) words = "is the supersampled reference itself (" + fmt(-dms) + " ms slower)";
    else if (dms > 0 && lost > 0.05) words = fmt(dms / lost, 2) + " ms per dB given up";
    else if (dms > 0) words = "saves time at no measurable loss";
    else words = "no saving on this machine (" + fmt(-dms) + " ms slower)";
    md << "| " << st.name << " | " << it->second.ms_saved.size() << " | " << fmt(dms) << " | "
       << (it->second.db.empty() ? std::string("—") : fmt(db) + " (max: " + fmt(base_db) + ")") << " | " << (it->second.db_ref_change.empty() ? "—" : (mean(it->second.db_ref_change) >= 0 ? "+" : "") + fmt(mean(it->second.db_ref_change)))
       << " | " << words << " |\n";
  }

  // The three most useful trades, chosen from the run of 2026-11-28 (docs/accuracy-vs-time.md
  // discusses why): the largest time saving for its loss (MSAA 4 -> 1), the largest accuracy gain
  // for its cost (the environment map, on the scenes that name one), and the one step that buys
  // accuracy beyond the maximum setting (2x supersampling). Numbers are this run's; "vs Blender"
  // is the change of PSNR against the authoring tool's reference, the integrator's question.
  struct Trade {
    std::string title, setting;
    bool inverse;  // the trade is base -> setting reversed (turning the feature ON costs the base's time)
    std::string words;
  };
  const std::vector<Trade> trades = {
      {"MSAA 4 -> 1", "msaa1", false,
       "the cheapest large saving: edges alias, shading is untouched, so the loss is largest where thin edges dominate (the cluster)"},
      {"environment map on (scenes that name one)", "no-env", true,
       "what the world image costs: one texture fetch and the ambient cube per fragment, only in the programs of scenes that have one"},
      {"2x supersampling on top of the maximum", "ss2x", false,
       "the only setting that gets closer to Blender than the default: EEVEE's 64-sample film filter is smoother than MSAA 4"},
  };
  md << "\n## The three most useful trades (this run, side by side)\n\n"
     << "| trade | scenes | frame time change (mean ms, base → setting) | dB vs Blender (mean change, min … max) | ms per dB vs Blender | dB vs supersampled (mean change) | what it means |\n"
        "|---|---|---|---|---|---|---|\n";
  std::string summary;
  auto signed_fmt = [&](double v) { return (v >= 0 ? "+" : "") + fmt(v); };
  auto signed_fmt_db = signed_fmt;
  for (const Trade& t : trades) {
    auto it = delta.find(t.setting);
    if (it == delta.end() || it->second.ms_saved.empty()) continue;
    const Delta& d = it->second;
    const double sign = t.inverse ? -1.0 : 1.0;  // the "on" direction of an inverse trade is base vs setting reversed
    const double base_ms = mean(d.base_ms), other_ms = base_ms - mean(d.ms_saved);
    const double from_ms = t.inverse ? other_ms : base_ms, to_ms = t.inverse ? base_ms : other_ms;
    double lo = INFINITY, hi = -INFINITY;
    for (double v : d.db_ref_change) lo = std::min(lo, sign * v), hi = std::max(hi, sign * v);
    const double ref_change = sign * mean(d.db_ref_change);
    const std::string ss_change = d.db.empty() ? "— (is the reference)" : signed_fmt_db(sign * (mean(d.db) - mean(d.base_db)));
    md << "| " << t.title << " | " << d.ms_saved.size() << " | " << fmt(from_ms) << " → " << fmt(to_ms) << " (" << signed_fmt(to_ms - from_ms)
       << " ms, " << signed_fmt(100.0 * (to_ms - from_ms) / std::max(1e-9, from_ms)) << " %) | " << signed_fmt(ref_change) << " ("
       << signed_fmt(lo) << " … " << signed_fmt(hi) << ") | "
       << (std::abs(ref_change) > 0.05 ? fmt(std::abs(to_ms - from_ms) / std::abs(ref_change)) : std::string("—")) << " | " << ss_change
       << " | " << t.words << " |\n";
    if (std::abs(ref_change) > 0.05)
      summary += (summary.empty() ? "" : "; ") + t.title + " " + (to_ms > from_ms ? "costs " : "saves ") +
                 fmt(std::abs(to_ms - from_ms) / std::abs(ref_change)) + " ms per dB it " + (ref_change > 0 ? "gains" : "gives up");
  }
  if (!summary.empty())
    md << "\nIn milliseconds per dB against the authoring tool (this run): " << summary
       << ". The environment map is the cheapest accuracy there is where a scene has one; dropping MSAA is the "
          "cheapest time; supersampling is the most expensive dB and only worth it where the budget is idle.\n";
  md << "\n## Every scene and setting\n\n| scene | setting | median ms | p99 ms | dB vs supersampled | dB vs Blender |\n|---|---|---|---|---|---|\n";
  for (const Point& p : points)
    md << "| " << p.scene << " | " << p.setting << " | " << fmt(p.median_ms) << " | " << fmt(p.p99_ms) << " | " << fmt(p.db_ss) << " | "
       << fmt(p.db_ref) << " |\n";
  if (!skipped.empty()) {
    md << "\nSkipped scenes:\n\n";
    for (const auto& s : skipped) md << "- " << s << "\n";
  }
  md << "\n## Keio cost model: time = A × object pixels + B\n\n"
     << "Fitted by least squares per shading model and LOD on the `specular` teapot scaled to " << scales.size()
     << " screen sizes (scale " << scales.front() << " … " << scales.back() << ", 640x480, MSAA 1; object pixels counted in each "
        "render), median frame times measured interleaved as above. Stored for the engine (frame-rate governor) in `"
     << fs::relative(model_file, kRoot).string() << "` (`meter-cost-model/1`).\n\n"
     << keio_md.str()
     << "\nB includes the per-frame work that does not scale with the object (clear, MSAA resolve of the whole target, "
        "glFinish round trip), which on llvmpipe dominates small objects.\n";
  std::ofstream(doc) << md.str();
  std::printf("wrote %s, %s, %s, %s (%.1f min)\n", (out / "accuracy.csv").c_str(), (out / "keio.csv").c_str(), model_file.c_str(),
              doc.c_str(), minutes);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"meter-bench: fidelity against the authoring tool and the cost of each quality level (issue #9)"};
  app.require_subcommand(1);
  std::string backend_name = "egl";
  std::string out_dir;
  std::string doc;
  auto* fid = app.add_subcommand("fidelity", "PSNR / SSIM of every scene vs its Blender reference -> docs/fidelity.md + CSV");
  fid->add_option("--backend", backend_name, "egl | osmesa")->check(CLI::IsMember({"egl", "osmesa"}));
  fid->add_option("--out", out_dir, "output directory (CSV, renders); default ./fidelity-out");
  fid->add_option("--doc", doc, "markdown file to write; default <source>/docs/fidelity.md (with --quality: DIR/fidelity.md)");
  std::string quality;
  fid->add_option("--quality", quality, "a quality-ladder point applied to every scene, e.g. environment=off (default: none)");
  int rounds = 3, frames = 5;
  std::string model = (kRoot / "bench/fidelity/cost-model.json").string();
  std::vector<std::string> only;
  auto* acc = app.add_subcommand("accuracy", "quality ladder: frame time vs PSNR, Keio cost model -> docs/accuracy-vs-time.md");
  acc->add_option("--backend", backend_name, "egl | osmesa")->check(CLI::IsMember({"egl", "osmesa"}));
  acc->add_option("--out", out_dir, "output directory (CSV); default ./accuracy-out");
  acc->add_option("--doc", doc, "markdown file to write; default <source>/docs/accuracy-vs-time.md");
  acc->add_option("--model", model, "cost-model JSON to write");
  acc->add_option("--rounds", rounds, "interleaved rounds")->check(CLI::Range(1, 1000));
  acc->add_option("--frames", frames, "frames per ladder point per round")->check(CLI::Range(1, 1000));
  acc->add_option("--scene", only, "only these scenes (repeatable)");
  CLI11_PARSE(app, argc, argv);
  const auto kind = *platform::parse_backend_kind(backend_name);
  try {
    if (*fid) {
      // A degraded run must not overwrite the committed table of the product's defaults.
      const fs::path dir = out_dir.empty() ? "fidelity-out" : out_dir;
      const fs::path d = !doc.empty() ? fs::path(doc) : quality.empty() ? kRoot / "docs/fidelity.md" : dir / "fidelity.md";
      return run_fidelity(kind, dir, d, quality);
    }
    return run_accuracy(kind, out_dir.empty() ? "accuracy-out" : out_dir, doc.empty() ? kRoot / "docs/accuracy-vs-time.md" : fs::path(doc),
                        model, rounds, frames, only);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meter-bench: %s\n", e.what());
    return 1;
  }
}
