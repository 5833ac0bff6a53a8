// The keys one end of an authenticated link holds: its key file, read at start and again whenever
// the file changes (checked before each new connection and once a second), so keys rotate without
// a restart. A file that turns bad keeps the keys already read (and says why).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <ctime>
#include <string>
#include <vector>

#include "meter/protocol/key_file.hpp"

namespace meter::protocol::detail {

class KeyRing {
 public:
  // Reads the file; std::runtime_error with the loader's message if it is not a good key file.
  explicit KeyRing(std::string path);
  // Re-reads the file if its inode, size or modification time changed. True if the keys changed;
  // `error` gets the reason a changed file was not taken ("" otherwise).
  bool refresh(std::string& error);
  // refresh() at most once a second (at once with `now`), logging a file that turned bad or the
  // keys taken; `who` names this end in the log. True if the keys changed.
  bool poll(const std::string& who, bool now);
  const LinkKey& current() const { return keys_.front(); }  // the key this end tags with
  const FrameKey* find(std::uint32_t id) const;
  const std::string& path() const { return path_; }
  std::string ids() const;  // "1, 2": for messages

 private:
  bool changed_on_disk();
  std::string path_;
  std::vector<LinkKey> keys_;
  ino_t inode_ = 0;
  off_t size_ = 0;
  timespec mtime_{};
  std::chrono::steady_clock::time_point next_poll_{};
};

}  // namespace meter::protocol::detail
