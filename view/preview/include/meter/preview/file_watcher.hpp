// Watches files for saves through inotify on the folders that hold them: editors and exporters
// save by writing a temporary file and renaming it over the old one, which a watch on the file
// itself would lose (it follows the replaced inode); a watch on the folder sees the new name arrive.
#pragma once

#include <filesystem>
#include <vector>

namespace meter::preview {

class FileWatcher {
 public:
  // Watches the folders of `files` (the files need not exist yet). Throws std::runtime_error
  // naming the folder and the system's reason when a folder cannot be watched.
  explicit FileWatcher(std::vector<std::filesystem::path> files);
  ~FileWatcher();
  FileWatcher(const FileWatcher&) = delete;
  FileWatcher& operator=(const FileWatcher&) = delete;

  // Reads every pending event without blocking. Returns the watched files written, created,
  // renamed into place or removed since the last call, each once, in the order they were given
  // (all of them when the kernel's event queue overflowed).
  std::vector<std::filesystem::path> poll();
  // The inotify descriptor (readable when events are pending), for a caller's own poll().
  int fd() const { return fd_; }

 private:
  struct Watched {
    std::filesystem::path file;  // as given
    int wd = -1;                 // its folder's watch
    std::filesystem::path name;  // file name inside the folder
  };
  int fd_ = -1;
  std::vector<Watched> files_;
};

}  // namespace meter::preview
