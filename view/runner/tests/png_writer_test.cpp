// The PNG writer thread: files written with the right pixels, the queue bound, draining on
// finish, and write errors counted and reported to the render thread without stopping it.
#include "meter/runner/png_writer.hpp"

#include <atomic>
#include <future>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using ::testing::HasSubstr;

TEST(PngWriter, WritesEveryQueuedImageBeforeFinishReturns) {
  const auto dir = testing::scratch_dir();
  std::vector<std::uint64_t> written;
  std::mutex m;
  {
    PngWriter w([&](std::uint64_t frame) {
      std::lock_guard lock(m);
      written.push_back(frame);
    });
    for (std::uint64_t f = 0; f < 8; ++f) {
      platform::Image image(32, 16, static_cast<std::uint8_t>(f * 30), 10, 20);
      w.write(image, dir / ("f" + std::to_string(f) + ".png"), f, [] { std::this_thread::yield(); });
    }
    w.finish();
    w.check();
    EXPECT_EQ(written, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7})) << "in order, every one";
  }
  for (std::uint64_t f = 0; f < 8; ++f) {
    const auto image = platform::read_png(dir / ("f" + std::to_string(f) + ".png"));
    ASSERT_EQ(image.width, 32);
    ASSERT_EQ(image.height, 16);
    EXPECT_EQ(image.rgba[0], f * 30) << "frame " << f << " has its own pixels (the image is copied)";
  }
}

TEST(PngWriter, DestructorDrainsTheQueue) {
  const auto dir = testing::scratch_dir();
  {
    PngWriter w;
    for (int f = 0; f < 3; ++f) w.write(platform::Image(16, 16), dir / ("d" + std::to_string(f) + ".png"), 0, [] {});
  }
  for (int f = 0; f < 3; ++f) EXPECT_TRUE(std::filesystem::exists(dir / ("d" + std::to_string(f) + ".png"))) << f;
}

TEST(PngWriter, AFullQueueMakesTheCallerServiceWhileItWaits) {
  const auto dir = testing::scratch_dir();
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  PngWriter w([released](std::uint64_t) { released.wait(); });  // holds the first image "being written"
  int while_full_calls = 0;
  for (std::uint64_t f = 0; f < PngWriter::kMaxPending; ++f) {
    w.write(platform::Image(16, 16), dir / ("q" + std::to_string(f) + ".png"), f, [&] { ++while_full_calls; });
  }
  EXPECT_EQ(while_full_calls, 0) << "up to kMaxPending images queue without waiting";
  bool released_set = false;
  w.write(platform::Image(16, 16), dir / "q_last.png", 99, [&] {
    if (++while_full_calls == 3) {  // the caller's servicing lets the writer go on
      release.set_value();
      released_set = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  if (!released_set) release.set_value();
  EXPECT_GE(while_full_calls, 3);
  w.finish();
  w.check();
  EXPECT_TRUE(std::filesystem::exists(dir / "q_last.png")) << "the waiting image is written too";
}

TEST(PngWriter, AWriteErrorReachesTheRenderThread) {
  const auto dir = testing::scratch_dir();
  PngWriter w;
  const auto bad = dir / "no_such_dir" / "f.png";
  w.write(platform::Image(16, 16), bad, 0, [] {});
  w.write(platform::Image(16, 16), dir / "after.png", 1, [] {});
  w.finish();
  try {
    w.check();
    FAIL() << "no error reported";
  } catch (const ViewError& e) {
    EXPECT_THAT(e.what(), HasSubstr(bad.string())) << "the message names the file";
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "after.png")) << "one failed file does not stop the others";
  EXPECT_EQ(w.failures(), 1U);
  EXPECT_THAT(w.first_error(), HasSubstr(bad.string()));
}

TEST(PngWriter, AFailedFileIsCountedAndTheNextOnesAreStillWritten) {
  // A dump that fails must not stop the live view (it keeps drawing and reports the fault).
  const auto dir = testing::scratch_dir();
  PngWriter w;
  w.write(platform::Image(16, 16), dir / "missing" / "a.png", 0, [] {});
  w.write(platform::Image(16, 16), dir / "missing" / "b.png", 1, [] {});
  EXPECT_NO_THROW(w.write(platform::Image(16, 16), dir / "later.png", 2, [] {}));
  w.finish();
  EXPECT_EQ(w.failures(), 2U);
  EXPECT_THAT(w.first_error(), HasSubstr("a.png")) << "the first error is kept";
  EXPECT_TRUE(std::filesystem::exists(dir / "later.png"));
}

TEST(PngWriter, DropPolicyRefusesAFrameWhenFullWithoutWaiting) {
  // --dump-policy drop: a slow encoder never holds the render loop; the frame is counted.
  const auto dir = testing::scratch_dir();
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  PngWriter w([released](std::uint64_t) { released.wait(); });
  auto frame = [&](std::uint64_t n) {
    ReadbackFrame f;
    f.info.frame = n;
    f.info.png = dir / ("p" + std::to_string(n) + ".png");
    f.image = platform::Image(8, 4);
    return f;
  };
  int while_full_calls = 0;
  for (std::uint64_t n = 0; n < PngWriter::kMaxPending; ++n)
    EXPECT_TRUE(w.offer(frame(n), false, DumpOverflow::Drop, [&] { ++while_full_calls; })) << n;
  EXPECT_FALSE(w.offer(frame(9), false, DumpOverflow::Drop, [&] { ++while_full_calls; })) << "full: dropped";
  EXPECT_EQ(while_full_calls, 0) << "a drop never waits";
  EXPECT_EQ(w.dropped(), 1U);
  release.set_value();
  w.finish();
  EXPECT_FALSE(std::filesystem::exists(dir / "p9.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "p2.png"));
}

TEST(PngWriter, BottomUpRowsAreWrittenTopDown) {
  const auto dir = testing::scratch_dir();
  {
    PngWriter w;
    ReadbackFrame f;
    f.info.frame = 1;
    f.info.png = dir / "c1.png";
    f.image = platform::Image(4, 2, 10, 0, 0);
    f.image.pixel(0, 1)[0] = 200;  // GL's first row is the image's bottom row
    w.offer(std::move(f), true, DumpOverflow::Block, [] {});
  }
  const auto png = platform::read_png(dir / "c1.png");
  EXPECT_EQ(png.rgba[0], 200) << "bottom-up rows are flipped before encoding";
  EXPECT_EQ(png.pixel(0, 1)[0], 10);
}

}  // namespace
}  // namespace meter::runner
