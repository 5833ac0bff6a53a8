// CPU images, PNG files and the image-comparison metrics used by the render tests and by the
// fidelity benchmark: PSNR (full frame and masked to object pixels) and SSIM.
// Pure functions on plain data: no GL needed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace meter::platform {

// 8-bit RGBA, rows top-down, no padding: pixel (x, y) starts at rgba[4 * (y * width + x)].
// Colour values are sRGB-encoded as stored in PNG files and sRGB render targets.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;

  Image() = default;
  // A width x height image filled with one colour. Throws std::invalid_argument on sizes <= 0.
  Image(int w, int h, std::uint8_t r = 0, std::uint8_t g = 0, std::uint8_t b = 0, std::uint8_t a = 255);

  bool empty() const { return width == 0 || height == 0; }
  std::uint8_t* pixel(int x, int y) { return rgba.data() + 4 * (static_cast<std::size_t>(y) * width + x); }
  const std::uint8_t* pixel(int x, int y) const {
    return rgba.data() + 4 * (static_cast<std::size_t>(y) * width + x);
  }
  friend bool operator==(const Image&, const Image&) = default;
};

// Thrown by read_png / write_png; the message names the file and what went wrong.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes an 8-bit RGBA PNG (lossless). Throws ImageError naming the file.
void write_png(const Image& image, const std::filesystem::path& file);
// Reads any PNG libpng understands (grey, palette, RGB, 16-bit, ...) converted to 8-bit RGBA.
// Throws ImageError naming the file and the problem (missing, not a PNG, truncated, ...).
Image read_png(const std::filesystem::path& file);

// Per-pixel selection with the same size as an image; non-zero = selected.
struct Mask {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> on;
  std::size_t count() const;
};

// PSNR in dB over R, G and B of all pixels (alpha ignored), peak 255:
//   10 * log10(255^2 / MSE). Identical images give +infinity; all-black vs all-white gives 0 dB.
// Throws std::invalid_argument when the sizes differ or the images are empty.
double psnr(const Image& a, const Image& b);
// PSNR over the pixels selected by `mask` only (the paper's "object pixels" column).
// Throws std::invalid_argument on size mismatch or an empty selection.
double psnr_masked(const Image& a, const Image& b, const Mask& mask);
// Mean SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luma Y = 0.299 R + 0.587 G + 0.114 B:
// 11x11 Gaussian window, sigma 1.5, K1 = 0.01, K2 = 0.03, L = 255, averaged over every window that
// fits entirely inside the image (no padding). Identical images give exactly 1.0.
// Throws std::invalid_argument on size mismatch or images smaller than 11x11.
double ssim(const Image& a, const Image& b);
// Pixels of `reference` whose R, G or B differs from `background` by more than `tolerance`
// (0..255): the object pixels of a render on a known background colour.
struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};
Mask object_mask(const Image& reference, Rgb8 background, int tolerance);

}  // namespace meter::platform
