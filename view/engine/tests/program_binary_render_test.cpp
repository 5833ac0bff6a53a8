// The program-binary cache on a real driver (EGL, llvmpipe): a view started again loads its
// programs from the kept binaries, and every kept binary that is damaged, truncated, stored for
// another program or refused by the driver falls back to compiling: the image is the uncached
// one, byte for byte, in every case.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/gl/program_binary_cache.hpp"
#include "meter/engine/gl/program_binary_file.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/protocol/catalog.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
namespace fs = std::filesystem;

namespace {

const Scene& dial() {
  static Scene s = [] {
    auto dir = test::scratch_dir("program_binary");
    return convert::convert_gltf(test::write_dial_scene(dir), config::parse_scene_config(test::dial_config_json()),
                                 convert::ConvertOptions{true}).scene;
  }();
  return s;
}

class ProgramBinaryRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Mesa offers a binary format only with its shader cache on: on, in a directory of its own.
    unsetenv("MESA_SHADER_CACHE_DISABLE");
    setenv("MESA_SHADER_CACHE_DIR", test::scratch_dir("program_binary_mesa").c_str(), 1);
    backend_ = platform::create_backend(platform::BackendKind::Egl).release();
  }
  static void TearDownTestSuite() { delete backend_; }
  void SetUp() override {
    ASSERT_TRUE(backend_->gl().info.has_program_binary) << "llvmpipe offers no program binary format";
    dir_ = test::scratch_dir("program_binary_cache");
    if (uncached_.width == 0) uncached_ = render(nullptr);
  }

  // The dial at 100 km/h, drawn by a fresh renderer linking through `cache`.
  platform::Image render(ProgramBinaryCache* cache) {
    RendererOptions o;
    o.msaa = 4;
    o.program_binaries = cache;
    Renderer renderer(*backend_, dial(), o);
    BindingEvaluator evaluator(dial());
    protocol::SignalTable values;
    values.set(protocol::sig::kSpeed, {100.0, protocol::SignalStatus::Valid, ""});
    evaluator.update(values, true, -1.0);
    renderer.apply(evaluator.outputs());
    renderer.render(true, true);
    return renderer.last_image();
  }
  // Renders through a fresh cache over dir_ and returns it (its counts) and the image.
  ProgramBinaryCache::Counts render_cached(platform::Image& image) {
    ProgramBinaryCache cache(dir_, log_);
    image = render(&cache);
    return cache.counts();
  }
  std::vector<fs::path> files() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
  }
  static void rewrite(const fs::path& file, const std::vector<std::uint8_t>& bytes) {
    std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(bytes.data()),
                                                                   static_cast<std::streamsize>(bytes.size()));
  }
  static std::vector<std::uint8_t> bytes_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // Stores every program (a cold run), then damages every kept file with `damage` and checks the
  // next run compiles each, refuses each, draws the uncached image and leaves good files behind.
  template <class Damage>
  void expect_fallback(Damage damage) {
    platform::Image image;
    const auto cold = render_cached(image);
    ASSERT_GT(cold.stored, 0u);
    const auto kept = files();
    for (std::size_t i = 0; i < kept.size(); ++i) damage(kept, i);
    const auto next = render_cached(image);
    EXPECT_EQ(next.refused, kept.size()) << log_.str();
    EXPECT_EQ(next.loaded, 0u);
    EXPECT_EQ(next.compiled, cold.compiled);
    EXPECT_EQ(image.rgba, uncached_.rgba);
    const auto again = render_cached(image);  // the refused files were replaced by good ones
    EXPECT_EQ(again.loaded, cold.compiled);
    EXPECT_EQ(again.refused, 0u);
    EXPECT_EQ(image.rgba, uncached_.rgba);
  }

  static inline platform::GpuBackend* backend_ = nullptr;
  static inline platform::Image uncached_;
  fs::path dir_;
  std::ostringstream log_;
};

}  // namespace

TEST_F(ProgramBinaryRender, ARestartLoadsEveryProgramAndAnUnwritableDirectoryCostsTheCompileOnly) {
  platform::Image image;
  const auto cold = render_cached(image);
  EXPECT_GT(cold.compiled, 0u);
  EXPECT_EQ(cold.stored, cold.compiled);
  EXPECT_EQ(cold.loaded, 0u);
  EXPECT_EQ(files().size(), cold.stored);  // no temporary file left
  EXPECT_EQ(image.rgba, uncached_.rgba);
  const auto warm = render_cached(image);
  EXPECT_EQ(warm.loaded, cold.compiled);
  EXPECT_EQ(warm.compiled, 0u);
  EXPECT_EQ(warm.refused, 0u);
  EXPECT_EQ(image.rgba, uncached_.rgba);

  // A file where the directory should be: nothing can be stored, said once, the compile is the cost.
  const fs::path file = dir_ / "not-a-directory";
  rewrite(file, {1});
  dir_ = file;
  const auto counts = render_cached(image);
  EXPECT_EQ(counts.stored, 0u);
  EXPECT_EQ(counts.compiled, cold.compiled);
  EXPECT_EQ(image.rgba, uncached_.rgba);
  const std::string log = log_.str();
  EXPECT_NE(log.find("cannot store program binaries there"), std::string::npos) << log;
  EXPECT_EQ(log.find("cannot store"), log.rfind("cannot store")) << "said once: " << log;
}

// One process for every kind of bad kept binary (a GL test's start is most of its cost); each kind
// on a fresh directory.
TEST_F(ProgramBinaryRender, EveryBadKeptBinaryIsCompiledInstead) {
  {
    SCOPED_TRACE("damaged");
    expect_fallback([&](const std::vector<fs::path>& kept, std::size_t i) {
      auto bytes = bytes_of(kept[i]);
      bytes[bytes.size() / 2 + 44] ^= 0x5a;  // inside the driver's binary
      rewrite(kept[i], bytes);
    });
    EXPECT_NE(log_.str().find("does not match its digest"), std::string::npos) << log_.str();
  }
  {
    SCOPED_TRACE("truncated");
    dir_ = test::scratch_dir("program_binary_cache_truncated");
    expect_fallback([&](const std::vector<fs::path>& kept, std::size_t i) {
      auto bytes = bytes_of(kept[i]);
      bytes.resize(i % 2 ? 60 : bytes.size() - 1);  // a cut header, a cut binary
      rewrite(kept[i], bytes);
    });
  }
  {
    SCOPED_TRACE("stale: another program's binary under this name");
    dir_ = test::scratch_dir("program_binary_cache_stale");
    expect_fallback([&](const std::vector<fs::path>& kept, std::size_t i) {
      ASSERT_GT(kept.size(), 1u);
      rewrite(kept[i], bytes_of(kept[(i + 1) % kept.size()]));
    });
    EXPECT_NE(log_.str().find("another driver or other sources"), std::string::npos) << log_.str();
  }
  {
    SCOPED_TRACE("foreign: a well-formed file for this key whose binary another driver made");
    dir_ = test::scratch_dir("program_binary_cache_foreign");
    expect_fallback([&](const std::vector<fs::path>& kept, std::size_t i) {
      const std::string hex = kept[i].stem().string();
      ProgramBinaryKey key{};
      for (std::size_t b = 0; b < key.size(); ++b)
        key[b] = static_cast<std::uint8_t>(std::stoi(hex.substr(2 * b, 2), nullptr, 16));
      const auto good = decode_program_binary(bytes_of(kept[i]), key);
      ASSERT_TRUE(good.binary) << good.problem;
      ProgramBinary foreign = *good.binary;
      if (i % 2) foreign.format ^= 0x1;  // a format this driver does not know
      else for (std::size_t b = 0; b < foreign.bytes.size(); b += 7) foreign.bytes[b] ^= 0xff;  // its format, other bytes
      rewrite(kept[i], encode_program_binary(key, foreign));
    });
    EXPECT_NE(log_.str().find("the driver"), std::string::npos) << log_.str();
  }
}

