// Comparing a render with its reference: PSNR, SSIM, where the difference is, downsampling.
#include <algorithm>
#include <cmath>
#include <string>

#include "bench_scenes.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::bench {

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

namespace {

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

}  // namespace

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

}  // namespace meter::bench
