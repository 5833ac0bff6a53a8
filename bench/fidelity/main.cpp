// meter-bench: what accuracy costs in time, one subcommand per benchmark.
//
//   meter-bench fidelity [--backend egl|osmesa] [--out DIR] [--doc FILE] [--quality SPEC]
//     Renders the twelve feature scenes and the cluster in-process (convert_gltf + Renderer, the
//     product path: optimized programs, MSAA 4) and compares each with its Blender reference:
//     PSNR over the full frame, PSNR over the object pixels (object_mask of the reference against
//     its background colour, tolerance 8 levels) and SSIM. Writes DIR/fidelity.csv, the renders,
//     and docs/fidelity.md (the paper's Table 1 beside ours).
//
//   meter-bench accuracy [--backend egl|osmesa] [--out DIR] [--doc FILE] [--rounds N] [--frames N]
//     For each scene x quality-ladder point (quality_ladder.hpp): median and p99 frame time, measured
//     interleaved (round r draws K frames of every ladder point in turn, R rounds), and PSNR
//     against (a) the engine's maximum quality supersampled (2x size, MSAA 4, box-filtered down in
//     linear light) and (b) the Blender reference. Then fits the Keio cost model
//     time = A * object_pixels + B per shading model and LOD on the teapot of `specular` scaled
//     to several screen sizes. Writes DIR/accuracy.csv, DIR/keio.csv, cost-model.json (--model)
//     and docs/accuracy-vs-time.md; bench/fidelity/plot.py draws the PNG.
//
//   meter-bench film [--backend egl|osmesa] [--out DIR] [--scene NAME...] [--passes N] [--converged N]
//     The engine's film filter resolve (MSAA 4) against EEVEE's way of sampling the same kernel:
//     N jittered passes of one sample per pixel (default: as many as the reference's Blender render), drawn by the
//     engine and averaged in float; the same passes mirrored; many passes (the kernel itself).
//     Prints a markdown table (draw time, PSNR against Blender and against the engine's resolve)
//     and writes DIR/film.csv and the images.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_scenes.hpp"
#include "benchmarks.hpp"

using namespace meter;
using namespace meter::bench;

int main(int argc, char** argv) {
  CLI::App app{"meter-bench: fidelity against the authoring tool and the cost of each quality level"};
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
  int passes = 0, converged = 256;
  auto* film = app.add_subcommand("film", "film filter resolve vs EEVEE's jittered passes drawn by the engine -> table + CSV");
  film->add_option("--backend", backend_name, "egl | osmesa")->check(CLI::IsMember({"egl", "osmesa"}));
  film->add_option("--out", out_dir, "output directory (CSV, images); default ./film-out");
  film->add_option("--scene", only, "only these scenes (repeatable); default: the cluster");
  film->add_option("--passes", passes, "EEVEE's render samples; default: each reference's own (cluster 32, feature scenes 64)")
      ->check(CLI::Range(1, 4096));
  film->add_option("--converged", converged, "passes of the near-exact kernel")->check(CLI::Range(1, 4096));
  CLI11_PARSE(app, argc, argv);
  const auto kind = *platform::parse_backend_kind(backend_name);
  try {
    if (*fid) {
      // A degraded run must not overwrite the committed table of the product's defaults.
      const fs::path dir = out_dir.empty() ? "fidelity-out" : out_dir;
      const fs::path d = !doc.empty() ? fs::path(doc) : quality.empty() ? kRoot / "docs/fidelity.md" : dir / "fidelity.md";
      return run_fidelity(kind, dir, d, quality);
    }
    if (*film)
      return run_film(kind, out_dir.empty() ? "film-out" : out_dir, only.empty() ? std::vector<std::string>{"cluster"} : only, passes,
                      converged);
    return run_accuracy(kind, out_dir.empty() ? "accuracy-out" : out_dir, doc.empty() ? kRoot / "docs/accuracy-vs-time.md" : fs::path(doc),
                        model, rounds, frames, only);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meter-bench: %s\n", e.what());
    return 1;
  }
}
