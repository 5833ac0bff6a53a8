// Image, PNG and metric tests: pure CPU code. The metric values are checked against closed-form
// cases and against two independent implementations (ImageMagick and scikit-image).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "meter/platform/image.hpp"

namespace mp = meter::platform;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "test-tmp" / "platform" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir;
}

// A picture with structure (gradient + disc) plus deterministic noise, so PSNR/SSIM are non-trivial.
mp::Image test_picture(int w, int h, unsigned seed, int noise) {
  mp::Image img(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> n(-noise, noise);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const int dx = x - w / 2, dy = y - h / 2;
      const bool disc = dx * dx + dy * dy < (h / 3) * (h / 3);
      const int base[3] = {x * 255 / w, y * 255 / h, disc ? 220 : 40};
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::clamp(base[c] + n(rng), 0, 255));
      p[3] = 255;
    }
  return img;
}

std::string run(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) out += buf;
  pclose(pipe);
  return out;
}

}  // namespace

TEST(Image, PngRoundTripIsLossless) {
  mp::Image img = test_picture(37, 23, 1, 60);  // odd sizes catch stride mistakes
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = static_cast<std::uint8_t>(i * 7);
  const fs::path file = temp_dir() / "round.png";
  mp::write_png(img, file);
  const mp::Image back = mp::read_png(file);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_TRUE(back == img);
}

TEST(Image, ReadPngMissingFileNamesIt) {
  const fs::path file = temp_dir() / "does-not-exist.png";
  try {
    mp::read_png(file);
    FAIL() << "expected ImageError";
  } catch (const mp::ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("does-not-exist.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

TEST(Image, ReadPngRejectsNonPngAndTruncatedFiles) {
  const fs::path dir = temp_dir();
  {
    std::ofstream(dir / "text.png") << "this is not a PNG file\n";
  }
  try {
    mp::read_png(dir / "text.png");
    FAIL() << "expected ImageError";
  } catch (const mp::ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("text.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a readable PNG"), std::string::npos) << e.what();
  }
  // A valid PNG cut in half: the header parses, the pixel data does not.
  mp::write_png(test_picture(64, 64, 2, 50), dir / "full.png");
  const auto size = fs::file_size(dir / "full.png");
  fs::copy_file(dir / "full.png", dir / "half.png", fs::copy_options::overwrite_existing);
  fs::resize_file(dir / "half.png", size / 2);
  try {
    mp::read_png(dir / "half.png");
    FAIL() << "expected ImageError";
  } catch (const mp::ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("half.png"), std::string::npos) << e.what();
  }
}

TEST(Image, WritePngToMissingDirectoryNamesFile) {
  const fs::path file = temp_dir() / "no" / "such" / "dir" / "out.png";
  try {
    mp::write_png(mp::Image(4, 4), file);
    FAIL() << "expected ImageError";
  } catch (const mp::ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("out.png"), std::string::npos) << e.what();
  }
}

TEST(Image, RejectsNonPositiveSize) {
  EXPECT_THROW(mp::Image(0, 5), std::invalid_argument);
  EXPECT_THROW(mp::Image(5, -1), std::invalid_argument);
}

TEST(Psnr, IdenticalImagesAreInfinite) {
  const mp::Image a = test_picture(32, 32, 3, 30);
  EXPECT_EQ(mp::psnr(a, a), std::numeric_limits<double>::infinity());
}

TEST(Psnr, BlackVersusWhiteIsExactlyZero) {
  EXPECT_EQ(mp::psnr(mp::Image(16, 8, 0, 0, 0), mp::Image(16, 8, 255, 255, 255)), 0.0);
}

TEST(Psnr, KnownMse) {
  // Every channel off by one: MSE = 1 -> 20 log10(255).
  EXPECT_DOUBLE_EQ(mp::psnr(mp::Image(10, 10, 10, 20, 30), mp::Image(10, 10, 11, 21, 31)),
                   20.0 * std::log10(255.0));
  // Only blue off by 3: MSE = 9 / 3 = 3.
  EXPECT_DOUBLE_EQ(mp::psnr(mp::Image(7, 5, 0, 0, 0), mp::Image(7, 5, 0, 0, 3)),
                   10.0 * std::log10(255.0 * 255.0 / 3.0));
  // Half the pixels off by 10 in red: MSE = 0.5 * 100 / 3.
  mp::Image a(4, 4, 50, 50, 50), b = a;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) b.pixel(x, y)[0] = 60;
  EXPECT_DOUBLE_EQ(mp::psnr(a, b), 10.0 * std::log10(255.0 * 255.0 / (50.0 / 3.0)));
}

TEST(Psnr, IgnoresAlpha) {
  EXPECT_EQ(mp::psnr(mp::Image(4, 4, 1, 2, 3, 0), mp::Image(4, 4, 1, 2, 3, 255)),
            std::numeric_limits<double>::infinity());
}

TEST(Psnr, SizeMismatchThrows) {
  EXPECT_THROW(mp::psnr(mp::Image(4, 4), mp::Image(4, 5)), std::invalid_argument);
  EXPECT_THROW(mp::psnr(mp::Image(), mp::Image()), std::invalid_argument);
}

TEST(Psnr, MaskedCountsOnlySelectedPixels) {
  mp::Image ref(8, 8, 0, 0, 0), out = ref;
  ref.pixel(2, 2)[0] = 200;  // the "object": one red pixel
  out.pixel(2, 2)[0] = 190;  // rendered 10 off inside the object
  out.pixel(7, 7)[1] = 255;  // a large error outside the object
  const mp::Mask mask = mp::object_mask(ref, {0, 0, 0}, 2);
  ASSERT_EQ(mask.count(), 1u);
  EXPECT_DOUBLE_EQ(mp::psnr_masked(ref, out, mask), 10.0 * std::log10(255.0 * 255.0 / (100.0 / 3.0)));
  EXPECT_LT(mp::psnr(ref, out), mp::psnr_masked(ref, out, mask));
  mp::Mask empty{8, 8, std::vector<std::uint8_t>(64, 0)};
  EXPECT_THROW(mp::psnr_masked(ref, out, empty), std::invalid_argument);
  mp::Mask wrong{4, 4, std::vector<std::uint8_t>(16, 1)};
  EXPECT_THROW(mp::psnr_masked(ref, out, wrong), std::invalid_argument);
}

TEST(ObjectMask, ToleranceIsPerChannel) {
  mp::Image ref(3, 1, 10, 10, 10);
  ref.pixel(1, 0)[2] = 14;  // within tolerance 4
  ref.pixel(2, 0)[1] = 15;  // beyond
  const mp::Mask m = mp::object_mask(ref, {10, 10, 10}, 4);
  EXPECT_EQ(m.on, (std::vector<std::uint8_t>{0, 0, 1}));
  EXPECT_THROW(mp::object_mask(ref, {0, 0, 0}, 256), std::invalid_argument);
}

TEST(Ssim, IdenticalImagesAreExactlyOne) {
  const mp::Image a = test_picture(40, 30, 4, 40);
  EXPECT_EQ(mp::ssim(a, a), 1.0);
}

TEST(Ssim, ConstantImagesFollowTheLuminanceTerm) {
  // Flat images: variances are 0, so SSIM = (2 mx my + C1) / (mx^2 + my^2 + C1).
  const double c1 = (0.01 * 255) * (0.01 * 255);
  EXPECT_NEAR(mp::ssim(mp::Image(16, 16, 0, 0, 0), mp::Image(16, 16, 255, 255, 255)),
              c1 / (255.0 * 255.0 + c1), 1e-12);
  const double mx = 100.0, my = 150.0;  // grey: luma = value
  EXPECT_NEAR(mp::ssim(mp::Image(12, 12, 100, 100, 100), mp::Image(12, 12, 150, 150, 150)),
              (2 * mx * my + c1) / (mx * mx + my * my + c1), 1e-9);
}

TEST(Ssim, DropsWithNoiseAndIsSymmetric) {
  const mp::Image a = test_picture(48, 48, 5, 0);
  const mp::Image b = test_picture(48, 48, 6, 20);
  const mp::Image c = test_picture(48, 48, 7, 60);
  const double ab = mp::ssim(a, b), ac = mp::ssim(a, c);
  EXPECT_LT(ab, 1.0);
  EXPECT_LT(ac, ab);
  EXPECT_DOUBLE_EQ(ab, mp::ssim(b, a));
  EXPECT_THROW(mp::ssim(mp::Image(10, 20), mp::Image(10, 20)), std::invalid_argument);
}

// Independent implementations: ImageMagick's compare (PSNR over RGB, same formula) and
// scikit-image (PSNR and Gaussian SSIM with Wang's constants, on the same luma).
TEST(CrossCheck, PsnrMatchesImageMagick) {
  const fs::path dir = temp_dir();
  const mp::Image a = test_picture(96, 64, 8, 0), b = test_picture(96, 64, 9, 25);
  mp::write_png(a, dir / "a.png");
  mp::write_png(b, dir / "b.png");
  const std::string out = run("compare -metric PSNR '" + (dir / "a.png").string() + "' '" +
                              (dir / "b.png").string() + "' null: 2>&1");
  ASSERT_FALSE(out.empty()) << "ImageMagick 'compare' produced no output (package imagemagick)";
  const double theirs = std::stod(out);
  EXPECT_NEAR(mp::psnr(a, b), theirs, 1e-3) << "compare printed: " << out;
}

TEST(CrossCheck, PsnrAndSsimMatchScikitImage) {
  const fs::path dir = temp_dir();
  const mp::Image a = test_picture(80, 56, 10, 5), b = test_picture(80, 56, 11, 35);
  mp::write_png(a, dir / "a.png");
  mp::write_png(b, dir / "b.png");
  const fs::path script = dir / "metrics.py";
  {
    std::ofstream py(script);
    py << "import sys\n"
          "import numpy as np\n"
          "from skimage.io import imread\n"
          "from skimage.metrics import peak_signal_noise_ratio, structural_similarity\n"
          "a = imread(sys.argv[1])[..., :3].astype(np.float64)\n"
          "b = imread(sys.argv[2])[..., :3].astype(np.float64)\n"
          "w = np.array([0.299, 0.587, 0.114])\n"
          "print(repr(peak_signal_noise_ratio(a, b, data_range=255)))\n"
          "print(repr(structural_similarity(a @ w, b @ w, data_range=255, gaussian_weights=True,\n"
          "      sigma=1.5, use_sample_covariance=False, K1=0.01, K2=0.03)))\n";
  }
  const std::string out = run("/usr/bin/python3 '" + script.string() + "' '" + (dir / "a.png").string() +
                              "' '" + (dir / "b.png").string() + "' 2>&1");
  double their_psnr = 0, their_ssim = 0;
  ASSERT_EQ(std::sscanf(out.c_str(), "%lf %lf", &their_psnr, &their_ssim), 2)
      << "python3-skimage output: " << out;
  EXPECT_NEAR(mp::psnr(a, b), their_psnr, 1e-9);
  EXPECT_NEAR(mp::ssim(a, b), their_ssim, 1e-9);
}
