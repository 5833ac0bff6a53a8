// meter-bench accuracy: the quality ladder, frame time against PSNR, and the Keio cost model
// -> docs/accuracy-vs-time.md + CSV.
#include "benchmarks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"

#include "bench_scenes.hpp"

namespace meter::bench {

struct Ladder {
  std::string name, spec;
  int scale = 1;  // 2: drawn at twice the size and box-filtered down (supersampling; not a quality-ladder setting)
};

std::vector<Ladder> ladder() {
  // Base = the maximum per-step quality (PBR, highp, the scene's texture sampling: trilinear with
  // EEVEE's 2x anisotropy, full mesh, MSAA 4); every other point changes ONE setting, so each row
  // says what that one step costs and gives.
  const std::string base = "shading=pbr,precision=highp,msaa=4";
  return {{"max (pbr msaa4)", base},
          {"blinn-phong", "shading=blinn-phong,precision=highp,msaa=4"},
          {"gouraud", "shading=gouraud,precision=highp,msaa=4"},
          {"flat", "shading=flat,precision=highp,msaa=4"},
          {"unlit", "shading=unlit,precision=highp,msaa=4"},
          // MSAA 8 where the driver has it (llvmpipe clamps to 4: the row then equals the base).
          {"msaa8", "shading=pbr,precision=highp,msaa=8"},
          {"msaa2", "shading=pbr,precision=highp,msaa=2"},
          {"msaa1", "shading=pbr,precision=highp,msaa=1"},
          {"mediump", "shading=pbr,precision=mediump,msaa=4"},
          {"anisotropic", "shading=pbr,precision=highp,filter=anisotropic,msaa=4"},
          {"trilinear", "shading=pbr,precision=highp,filter=trilinear,msaa=4"},
          {"bilinear", "shading=pbr,precision=highp,filter=bilinear,msaa=4"},
          {"nearest", "shading=pbr,precision=highp,filter=nearest,msaa=4"},
          // The EClay paper's trade: no perspective correction of varyings.
          {"affine", base + ",interpolation=affine"},
          {"lod0.5", base + ",lod=0.5"},
          {"lod0.25", base + ",lod=0.25"},
          // Only scenes with an environment map measure this point (elsewhere it changes nothing).
          {"no-env", base + ",environment=off"},
          // Only scenes with lights that cast shadows measure this point (elsewhere there is no map).
          {"no-shadows", base + ",shadows=off"},
          // The MSAA resolve: the box or EEVEE's film filter (Blackman-Harris). The base is
          // the scene's own ("resolve" in its config: the film filter for every committed scene),
          // so on each scene one of the two rows is the base again and is left out.
          // Normal-mapped materials and mirrors shaded per MSAA sample
          // (sample_shading=normal-maps+mirrors) or per pixel; the base is the scene's own, so on
          // each scene one of the two is the base again and is left out, and scenes with neither
          // measure neither.
          {"per-sample-shading", base + ",sample_shading=normal-maps+mirrors"},
          {"per-pixel-shading", base + ",sample_shading=off"},
          {"box-resolve", base + ",resolve=box"},
          {"film-resolve", base + ",resolve=blackman-harris"},
          // The samples' storage: 8-bit sRGB (light above white clamped per sample) or half float
          // (clamped after the filter); the base is the scene's own, as for the resolve.
          {"float-samples", base + ",sample_format=rgba16f"},
          {"8-bit-samples", base + ",sample_format=srgb8"},
          // Supersampling on top of the maximum: the frame time is the 2x draw (the downsample, a
          // GPU blit on a target, is done on the CPU here and not timed). Box resolve, as (a).
          {"ss2x", base + ",resolve=box", 2},
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
    const auto q = convert::parse_quality(l.spec);
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
      // optimize = false: regenerated ladder programs are not constant-folded (quality_ladder.hpp), so the
      // base is unfolded too and only the ladder setting differs between rows.
      base = convert(s, false);
      state = reference_state(base, s.name == "cluster");
      if (!s.reference.empty()) ref = platform::read_png(s.reference);
      engine::RendererOptions big;
      big.width = base.config.size[0] * 2, big.height = base.config.size[1] * 2, big.msaa = 4;
      engine::Scene boxed = base;  // (a) is the box resolve at 2x, whatever the scene's own resolve
      boxed.config.resolve.filter = engine::ResolveConfig::Filter::Box;
      ss = downsample2(render_once(*backend, boxed, state, big));
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
      const convert::QualitySettings q = convert::parse_quality(steps[i].spec);
      try {
        const convert::QualityReport rep = convert::apply_quality(scenes[i], q);
        if (q.environment == false && !rep.environment_dropped) continue;  // no map: the base again
        if (q.shadows == false && rep.shadow_maps_dropped == 0) continue;  // nothing casts: the base again
        // A draw that either kind would shade per sample (the runtime's own test).
        const bridge::SampleShading every_kind{.normal_maps = true, .mirrors = true};
        const bool varies = std::any_of(base.draws.begin(), base.draws.end(), [&](const auto& d) {
          const auto& prim = base.meshes[std::size_t(d.mesh)].primitives[std::size_t(d.primitive)];
          return every_kind.shades_per_sample(base.programs[std::size_t(d.program)].program.features,
                                              base.materials[std::size_t(prim.material)].roughness);
        });
        if (q.sample_shading && (!varies || *q.sample_shading == base.config.sample_shading)) continue;  // the base again
        if (q.resolve && steps[i].scale == 1 && *q.resolve == base.config.resolve.filter) continue;  // the scene's own resolve
        if (q.sample_format && *q.sample_format == base.config.resolve.sample_format) continue;  // the scene's own samples
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
        convert::QualitySettings q = convert::parse_quality("shading=" + sh);
        if (lod < 1.0f) q.global.lod = lod;
        convert::apply_quality(sc[k], q);
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
  md << "# Accuracy vs time: what each quality step costs\n\n"
     << "Generated by `meter-bench accuracy --backend " << backend->name() << " --rounds " << rounds << " --frames " << frames
     << "` — re-run it rather than editing. Run time " << fmt(minutes, 1) << " min.\n\n"
     << "Machine and date: " << machine_line(*backend) << ". llvmpipe renders on the CPU, so these milliseconds are "
        "CPU time on a 2-core machine shared with other jobs: the ratios between rows, measured interleaved in one run, "
        "are the result, not the absolute values; a GPU target needs its own run.\n\n"
     << "Method: each scene is converted once (optimize off, so regenerated programs and the base differ only in the "
        "ladder setting) and every ladder point gets its own Renderer; round r draws " << frames << " frames of every point in turn, "
     << rounds << " rounds (" << rounds * frames << " frames per point; few, to keep the command to a few minutes — p99 over so few "
        "frames is close to the maximum). Frame time = `Renderer::render(force)` wall time, which includes glFinish (llvmpipe "
        "executes the frame there). PSNR (a) against the engine's maximum quality supersampled (PBR, highp, trilinear with 2x anisotropy, MSAA 4 "
        "drawn at 2x size and box-filtered to 1x in linear light) and (b) against the Blender reference. `no-env` (the "
        "environment map dropped, `environment=off`) runs only on the scenes that name one, `no-shadows` (`shadows=off`) only on the scenes whose lights cast shadows; `ss2x` is the maximum drawn at "
        "2x size (timed without the downsample, a GPU blit on a target) and is by construction identical to (a).\n\n"
     << "![frame time vs PSNR, Pareto front marked](images/accuracy-vs-time.png)\n\n";
  for (const auto& l : left_out) md << "Left out on this backend: " << l << ".\n\n";
  if (!plotted) md << "(The plot was not drawn: `" << cmd << "` failed; install python3-matplotlib, see scripts/install-deps.)\n\n";
  md << "## What each step buys, averaged over the scenes\n\n"
     << "Each row changes one setting from the maximum (PBR, highp, trilinear with 2x anisotropy, full mesh, MSAA 4). *ms saved* = base median − "
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
    const double ref_change = mean(it->second.db_ref_change);
    if (it->second.db.empty()) words = "is the supersampled reference itself (" + fmt(-dms) + " ms slower)";
    else if (lost <= 0.05 && ref_change < -0.05)  // e.g. the box resolve: nearer the (box) supersampled image, not Blender
      words = "no loss against the supersampled maximum but " + fmt(-ref_change) + " dB further from Blender";
    else if (dms > 0 && lost > 0.05) words = fmt(dms / lost, 2) + " ms per dB given up";
    else if (dms > 0) words = "saves time at no measurable loss";
    else words = "no saving on this machine (" + fmt(-dms) + " ms slower)";
    md << "| " << st.name << " | " << it->second.ms_saved.size() << " | " << fmt(dms) << " | "
       << (it->second.db.empty() ? std::string("—") : fmt(db) + " (max: " + fmt(base_db) + ")") << " | " << (it->second.db_ref_change.empty() ? "—" : (mean(it->second.db_ref_change) >= 0 ? "+" : "") + fmt(mean(it->second.db_ref_change)))
       << " | " << words << " |\n";
  }

  // The most useful trades, chosen from the runs of 2026-11-28 and 2026-12-02 (docs/accuracy-vs-time.md
  // discusses why): the largest time saving for its loss (MSAA 4 -> 1), the largest accuracy gain
  // for its cost (the environment map, on the scenes that name one), the film filter resolve (on
  // where it is off by default, off where it is on), and 2x supersampling on top of the maximum. Numbers are this run's; "vs Blender"
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
      {"shadow maps on (scenes whose lights cast shadows)", "no-shadows", true,
       "what shadows cost where the scene calls for them: one depth-compare lookup per casting light per fragment (here: the shadow scene, still, so each light's depth pass was drawn once; with a caster moving every frame the pass is drawn each frame too: `shadow_bench`); scenes whose lights cast none have neither"},
      {"film filter resolve on (scenes whose default is the box)", "film-resolve", false,
       "EEVEE's Blackman-Harris pixel filter over the MSAA samples of each 3 x 3 neighbourhood instead of the box (each pixel's own 4 samples, the same shader pass): edges spread as in the authoring tool's render. Its own cost is within this table's frame-to-frame noise on a shared machine (12 frames per point); measured alone, interleaved with the box, by `meter_platform_bench 30`: +12.5 ms a full 1280x480 frame on llvmpipe (28.3 ms against 15.7) (docs/scene-config.md, \"Resolve\")"},
      {"film filter resolve off (scenes whose default is the film filter)", "box-resolve", false,
       "what dropping the film filter for the box saves and loses on the scenes rendered with it (the time is within the noise here, see the row above)"},
      {"half-float samples on (scenes whose default is 8-bit)", "float-samples", false,
       "each MSAA sample stored as RGBA16F, light above white kept until the resolve has filtered it, instead of SRGB8_ALPHA8: twice the sample memory and bandwidth; it buys accuracy only where thin features are brighter than white"},
      {"half-float samples off (scenes that ask for them)", "8-bit-samples", false,
       "what 8-bit sRGB samples save and lose where a scene asks for half floats: edges of features brighter than white come out darker than in the authoring tool's float film"},
      {"2x anisotropic texture sampling on (EEVEE's, the default) instead of trilinear", "trilinear", true,
       "textures sampled along the pixel's footprint's long axis as EEVEE samples image textures (Blender's factory 2x); the environment map excluded"},
      {"per-sample shading of normal maps on (scenes with one, where it is off)", "per-sample-shading", false,
       "each MSAA sample of a normal-mapped material shaded on its own (GL_SAMPLE_SHADING) instead of once per pixel, on a scene that does not ask for it (the cluster's dial faces): up to 4x those draws' fragment work"},
      {"per-sample shading of normal maps off (scenes that ask for it)", "per-pixel-shading", false,
       "each MSAA sample of a normal-mapped material shaded on its own (GL_SAMPLE_SHADING) instead of once per pixel: the normal map's detail inside a pixel is averaged as EEVEE's many samples average it; only those draws pay, up to 4x their fragment work"},
      {"2x supersampling on top of the maximum", "ss2x", false,
       "the only setting that gets closer to Blender than the default: EEVEE's 64-sample film filter is smoother than MSAA 4"},
  };
  md << "\n## The most useful trades (this run, side by side)\n\n"
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

}  // namespace meter::bench
