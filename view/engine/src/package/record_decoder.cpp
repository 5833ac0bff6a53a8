// The package decoder's messages (record_decoder.hpp).
#include "record_decoder.hpp"

namespace meter::engine {

std::string RecordDecoder::path() const {
  std::string p;
  for (const Step& s : path_) {
    if (!p.empty()) p += '.';
    p += s.name;
    if (s.index >= 0) p += "[" + std::to_string(s.index) + "]";
  }
  return p;
}

void RecordDecoder::fail_at(const std::string& part, const std::string& what) const {
  throw SceneError(origin_ + ": corrupt package at byte " + std::to_string(offset_ + pos_) + " (chunk " + chunk_ + "): " +
                   path() + part + ": " + what);
}

}  // namespace meter::engine
