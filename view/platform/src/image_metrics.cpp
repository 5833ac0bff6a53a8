// Image comparison: PSNR (full frame and masked to object pixels), SSIM, object masks.
#include "meter/platform/image.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace meter::platform {

namespace {

void check_same_size(const Image& a, const Image& b, const char* what) {
  if (a.empty() || b.empty()) throw std::invalid_argument(std::string(what) + ": empty image");
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument(std::string(what) + ": sizes differ (" + std::to_string(a.width) +
                                "x" + std::to_string(a.height) + " vs " + std::to_string(b.width) +
                                "x" + std::to_string(b.height) + ")");
  }
  const std::size_t bytes = static_cast<std::size_t>(a.width) * a.height * 4;
  if (a.rgba.size() != bytes || b.rgba.size() != bytes) {
    throw std::invalid_argument(std::string(what) + ": pixel buffer size does not match width x height x 4");
  }
}

double psnr_from_sse(std::uint64_t sse, std::size_t samples) {
  if (sse == 0) return std::numeric_limits<double>::infinity();
  const double mse = static_cast<double>(sse) / static_cast<double>(samples);
  return 10.0 * std::log10((255.0 * 255.0) / mse);
}

}  // namespace

double psnr(const Image& a, const Image& b) {
  check_same_size(a, b, "psnr");
  std::uint64_t sse = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) {
      const int d = int(a.rgba[i + c]) - int(b.rgba[i + c]);
      sse += static_cast<std::uint64_t>(d * d);
    }
  }
  return psnr_from_sse(sse, a.rgba.size() / 4 * 3);
}

double psnr_masked(const Image& a, const Image& b, const Mask& mask) {
  check_same_size(a, b, "psnr_masked");
  if (mask.width != a.width || mask.height != a.height ||
      mask.on.size() != static_cast<std::size_t>(a.width) * a.height) {
    throw std::invalid_argument("psnr_masked: mask is " + std::to_string(mask.width) + "x" +
                                std::to_string(mask.height) + ", images are " +
                                std::to_string(a.width) + "x" + std::to_string(a.height));
  }
  std::uint64_t sse = 0;
  std::size_t pixels = 0;
  for (std::size_t p = 0; p < mask.on.size(); ++p) {
    if (!mask.on[p]) continue;
    ++pixels;
    for (int c = 0; c < 3; ++c) {
      const int d = int(a.rgba[4 * p + c]) - int(b.rgba[4 * p + c]);
      sse += static_cast<std::uint64_t>(d * d);
    }
  }
  if (pixels == 0) throw std::invalid_argument("psnr_masked: the mask selects no pixels");
  return psnr_from_sse(sse, pixels * 3);
}

namespace {

constexpr int kWindow = 11;
constexpr int kRadius = kWindow / 2;

// Separable 'valid' filtering: out is (w - 10) x (h - 10).
std::vector<double> filter_valid(const std::vector<double>& in, int w, int h, const double* k) {
  const int ow = w - 2 * kRadius, oh = h - 2 * kRadius;
  std::vector<double> tmp(static_cast<std::size_t>(ow) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int i = 0; i < kWindow; ++i) s += k[i] * in[static_cast<std::size_t>(y) * w + x + i];
      tmp[static_cast<std::size_t>(y) * ow + x] = s;
    }
  std::vector<double> out(static_cast<std::size_t>(ow) * oh);
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int i = 0; i < kWindow; ++i) s += k[i] * tmp[static_cast<std::size_t>(y + i) * ow + x];
      out[static_cast<std::size_t>(y) * ow + x] = s;
    }
  return out;
}

}  // namespace

double ssim(const Image& a, const Image& b) {
  check_same_size(a, b, "ssim");
  if (a.width < kWindow || a.height < kWindow) {
    throw std::invalid_argument("ssim: images are " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + ", need at least 11x11 (window size)");
  }
  // Gaussian window, sigma 1.5, normalised; the 2-D window is the outer product (also normalised).
  double kernel[kWindow];
  double sum = 0;
  for (int i = 0; i < kWindow; ++i) {
    const double d = i - kRadius;
    kernel[i] = std::exp(-(d * d) / (2.0 * 1.5 * 1.5));
    sum += kernel[i];
  }
  for (double& v : kernel) v /= sum;

  const int w = a.width, h = a.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  for (std::size_t p = 0; p < n; ++p) {
    const std::uint8_t* pa = &a.rgba[4 * p];
    const std::uint8_t* pb = &b.rgba[4 * p];
    x[p] = 0.299 * pa[0] + 0.587 * pa[1] + 0.114 * pa[2];
    y[p] = 0.299 * pb[0] + 0.587 * pb[1] + 0.114 * pb[2];
    xx[p] = x[p] * x[p];
    yy[p] = y[p] * y[p];
    xy[p] = x[p] * y[p];
  }
  const auto mx = filter_valid(x, w, h, kernel);
  const auto my = filter_valid(y, w, h, kernel);
  const auto mxx = filter_valid(xx, w, h, kernel);
  const auto myy = filter_valid(yy, w, h, kernel);
  const auto mxy = filter_valid(xy, w, h, kernel);
  const double c1 = (0.01 * 255.0) * (0.01 * 255.0);
  const double c2 = (0.03 * 255.0) * (0.03 * 255.0);
  double total = 0;
  for (std::size_t i = 0; i < mx.size(); ++i) {
    const double sx = mxx[i] - mx[i] * mx[i];
    const double sy = myy[i] - my[i] * my[i];
    const double sxy = mxy[i] - mx[i] * my[i];
    total += ((2 * mx[i] * my[i] + c1) * (2 * sxy + c2)) /
             ((mx[i] * mx[i] + my[i] * my[i] + c1) * (sx + sy + c2));
  }
  return total / static_cast<double>(mx.size());
}

Mask object_mask(const Image& reference, Rgb8 background, int tolerance) {
  if (reference.empty()) throw std::invalid_argument("object_mask: empty reference image");
  if (tolerance < 0 || tolerance > 255) {
    throw std::invalid_argument("object_mask: tolerance " + std::to_string(tolerance) +
                                " outside 0..255");
  }
  Mask mask;
  mask.width = reference.width;
  mask.height = reference.height;
  mask.on.resize(static_cast<std::size_t>(reference.width) * reference.height);
  for (std::size_t p = 0; p < mask.on.size(); ++p) {
    const std::uint8_t* px = &reference.rgba[4 * p];
    const bool differs = std::abs(int(px[0]) - background.r) > tolerance ||
                         std::abs(int(px[1]) - background.g) > tolerance ||
                         std::abs(int(px[2]) - background.b) > tolerance;
    mask.on[p] = differs ? 1 : 0;
  }
  return mask;
}

}  // namespace meter::platform
