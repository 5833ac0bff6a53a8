#include "meter/preview/file_watcher.hpp"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace meter::preview {
namespace {

// A save by rename arrives as IN_MOVED_TO, an in-place write as IN_CLOSE_WRITE (IN_MODIFY for
// writers that keep the file open), a save by delete + create as IN_DELETE then IN_CREATE.
constexpr std::uint32_t kSaveEvents = IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_MODIFY | IN_DELETE;

std::filesystem::path folder_of(const std::filesystem::path& file) {
  const auto parent = file.parent_path();
  return parent.empty() ? std::filesystem::path(".") : parent;
}

}  // namespace

FileWatcher::FileWatcher(std::vector<std::filesystem::path> files) {
  fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(std::string("inotify_init1: ") + std::strerror(errno));
  for (auto& file : files) {
    const auto folder = folder_of(file);
    const int wd = inotify_add_watch(fd_, folder.c_str(), kSaveEvents);
    if (wd < 0) {
      const std::string why = std::strerror(errno);
      close(fd_);
      throw std::runtime_error(folder.string() + ": cannot watch the folder for saves of " +
                               file.filename().string() + ": " + why);
    }
    files_.push_back({file, wd, file.filename()});
  }
}

FileWatcher::~FileWatcher() {
  if (fd_ >= 0) close(fd_);
}

std::vector<std::filesystem::path> FileWatcher::poll() {
  std::vector<bool> hit(files_.size(), false);
  alignas(inotify_event) char buffer[16384];
  for (;;) {
    const ssize_t n = read(fd_, buffer, sizeof buffer);
    if (n <= 0) break;  // EAGAIN: nothing more pending
    for (ssize_t at = 0; at < n;) {
      inotify_event event;
      std::memcpy(&event, buffer + at, sizeof event);
      const char* name = buffer + at + sizeof(inotify_event);
      at += static_cast<ssize_t>(sizeof(inotify_event) + event.len);
      for (std::size_t i = 0; i < files_.size(); ++i) {
        if ((event.mask & IN_Q_OVERFLOW) != 0 ||
            (event.wd == files_[i].wd && event.len > 0 && files_[i].name == name))
          hit[i] = true;
      }
    }
  }
  std::vector<std::filesystem::path> changed;
  for (std::size_t i = 0; i < files_.size(); ++i) {
    if (hit[i]) changed.push_back(files_[i].file);
  }
  return changed;
}

}  // namespace meter::preview
