#include "link/key_ring.hpp"

#include <sys/stat.h>

#include <stdexcept>

#include "transport/log.hpp"

namespace meter::protocol::detail {

KeyRing::KeyRing(std::string path) : path_(std::move(path)) {
  changed_on_disk();  // remember the file's identity before reading it
  auto loaded = load_key_file(path_);
  if (!loaded.error.empty()) throw std::runtime_error(loaded.error);
  keys_ = std::move(loaded.keys);
}

bool KeyRing::changed_on_disk() {
  struct stat st{};
  if (::stat(path_.c_str(), &st) != 0) return false;  // gone: keep the keys, the next change is read
  const bool changed = st.st_ino != inode_ || st.st_size != size_ || st.st_mtim.tv_sec != mtime_.tv_sec ||
                       st.st_mtim.tv_nsec != mtime_.tv_nsec;
  inode_ = st.st_ino;
  size_ = st.st_size;
  mtime_ = st.st_mtim;
  return changed;
}

bool KeyRing::refresh(std::string& error) {
  error.clear();
  if (!changed_on_disk()) return false;
  auto loaded = load_key_file(path_);
  if (!loaded.error.empty()) {
    error = loaded.error + " (keeping the " + std::to_string(keys_.size()) + " key(s) read before)";
    return false;
  }
  keys_ = std::move(loaded.keys);
  return true;
}

bool KeyRing::poll(const std::string& who, bool now) {
  const auto t = std::chrono::steady_clock::now();
  if (!now && t < next_poll_) return false;
  next_poll_ = t + std::chrono::seconds(1);
  std::string error;
  const bool changed = refresh(error);
  if (!error.empty()) log_limited("key-file", who + ": " + error);
  if (changed) log_limited("key-file", who + ": read " + path_ + " again (keys " + ids() + ")", LogLevel::Info);
  return changed;
}

const FrameKey* KeyRing::find(std::uint32_t id) const {
  for (const auto& k : keys_) {
    if (k.id == id) return &k.key;
  }
  return nullptr;
}

std::string KeyRing::ids() const {
  std::string out;
  for (const auto& k : keys_) out += (out.empty() ? "" : ", ") + std::to_string(k.id);
  return out;
}

}  // namespace meter::protocol::detail
