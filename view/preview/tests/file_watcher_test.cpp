// The save watcher: saves by rename, in place and by delete + create are seen on the watched files
// only, each file once per poll.
#include "meter/preview/file_watcher.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "preview_files.hpp"

namespace meter::preview {
namespace {

using testing::scratch_dir;
using testing::save_by_rename;
using testing::save_in_place;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

TEST(FileWatcher, SeesASaveByRenameOverTheWatchedFile) {
  const auto dir = scratch_dir();
  save_in_place(dir / "scene.json", "{}");
  FileWatcher w({dir / "scene.json"});
  EXPECT_TRUE(w.poll().empty());
  save_by_rename(dir / "scene.json", "{\"a\": 1}");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "scene.json"));
  EXPECT_TRUE(w.poll().empty()) << "events are consumed by the poll that reported them";
  // The watch is on the folder, so the next rename (a new inode again) is seen too.
  save_by_rename(dir / "scene.json", "{\"a\": 2}");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "scene.json"));
}

TEST(FileWatcher, SeesInPlaceWritesAndDeleteThenCreate) {
  const auto dir = scratch_dir();
  save_in_place(dir / "scene.glb", "x");
  FileWatcher w({dir / "scene.glb"});
  save_in_place(dir / "scene.glb", "yy");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "scene.glb"));
  fs::remove(dir / "scene.glb");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "scene.glb"));
  save_in_place(dir / "scene.glb", "zzz");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "scene.glb"));
}

TEST(FileWatcher, IgnoresOtherFilesInTheFolderAndReportsEachWatchedFileOnce) {
  const auto dir = scratch_dir();
  fs::create_directories(dir / "configs");
  save_in_place(dir / "a.glb", "a");
  save_in_place(dir / "configs" / "a.scene.json", "{}");
  FileWatcher w({dir / "a.glb", dir / "configs" / "a.scene.json"});
  save_in_place(dir / "b.glb", "other");
  save_by_rename(dir / "configs" / "b.scene.json", "{}");
  EXPECT_TRUE(w.poll().empty()) << "files beside the watched ones are not the artist's scene";
  // Several events of one save (temporary written, renamed), and both files, in the order given.
  save_by_rename(dir / "configs" / "a.scene.json", "{\"b\": 1}");
  save_in_place(dir / "a.glb", "aa");
  save_in_place(dir / "a.glb", "aaa");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "a.glb", dir / "configs" / "a.scene.json"));
}

TEST(FileWatcher, BothFilesInOneFolderShareItsWatch) {
  const auto dir = scratch_dir();
  save_in_place(dir / "s.glb", "g");
  save_in_place(dir / "s.json", "{}");
  FileWatcher w({dir / "s.glb", dir / "s.json"});
  save_by_rename(dir / "s.json", "{ }");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "s.json"));
  save_by_rename(dir / "s.glb", "gg");
  EXPECT_THAT(w.poll(), ElementsAre(dir / "s.glb"));
}

TEST(FileWatcher, AFolderThatCannotBeWatchedIsNamed) {
  const auto dir = scratch_dir();
  try {
    FileWatcher w({dir / "missing" / "scene.json"});
    FAIL() << "no error for a folder that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr((dir / "missing").string()));
    EXPECT_THAT(e.what(), HasSubstr("scene.json"));
    EXPECT_THAT(e.what(), HasSubstr("No such file or directory"));
  }
}

}  // namespace
}  // namespace meter::preview
