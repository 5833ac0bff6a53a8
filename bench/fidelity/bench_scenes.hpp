// The scenes meter-bench measures against their Blender references, and what both benchmarks
// share: loading a scene as shipped, the state each reference shows, one render, image
// comparison (PSNR, SSIM, where the difference is), a supersampling downsample and the run's
// machine line.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"

namespace meter::bench {

namespace fs = std::filesystem;

inline const fs::path kRoot = METER_SOURCE_DIR;
constexpr int kMaskTolerance = 8;  // levels: JPEG/dither noise on the background is below it

struct SceneSpec {
  std::string name, glb, config, reference;  // reference: PNG or JPEG ("" = none)
  double paper_db = -1.0;                    // the paper's Table 1 (DENSO), -1 = no counterpart
  std::string paper_name;
};

// The twelve feature scenes (with the paper's Table 1 value) and the cluster.
std::vector<SceneSpec> all_scenes();
// The state each reference shows (tests/support/reference_state.hpp, shared with the fidelity test).
engine::BindingOutputs reference_state(const engine::Scene& scene, bool cluster);
// The scene as shipped (concatenation groups included), optimized programs or not.
engine::Scene convert(const SceneSpec& s, bool optimize);
platform::Image render_once(platform::GpuBackend& backend, const engine::Scene& scene, const engine::BindingOutputs& state,
                            engine::RendererOptions o);
// Date, CPU, cores, kernel and GL renderer of this run, for the documents' headers.
std::string machine_line(const platform::GpuBackend& backend);
// A number for the tables: "—" for NaN, "identical" for an infinite PSNR.
std::string fmt(double v, int prec = 2);
double percentile(std::vector<double> v, double p);
// 2x2 box filter in linear light (averaging sRGB codes darkens edges).
platform::Image downsample2(const platform::Image& big);
std::size_t count_non_background(const platform::Image& img);

struct Metrics {
  double full = 0, object = 0, ssim = 0, object_share = 0;
};
// Full-frame PSNR, PSNR over the reference's object pixels, SSIM.
Metrics compare(const platform::Image& img, const platform::Image& ref);

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

Breakdown breakdown(const platform::Image& img, const platform::Image& ref);

}  // namespace meter::bench
