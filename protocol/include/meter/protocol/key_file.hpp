// The link key file: the shared secrets both ends of an authenticated link read (docs/security.md
// says how to provision and rotate them). Text, one key per line:
//
//   # comment
//   <key id, 1..4294967295> <64 hex digits: 32 key bytes>
//
// The first key is the one this end tags its frames with; the others are accepted from a peer that
// names them in its HELLO (a rotation in progress). The file must be a regular file owned by the
// user the process runs as, with no permission bits for group or others (mode 0600 or 0400).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/frame_tag.hpp"

namespace meter::protocol {

struct LinkKey {
  std::uint32_t id = 0;
  FrameKey key;
};

struct KeyFileResult {
  std::vector<LinkKey> keys;  // in file order; empty when error is set
  std::string error;          // "FILE:LINE: what was expected", or "" when the file is good
};

inline constexpr std::size_t kMaxKeyFileBytes = 65536;

// Parses the text of a key file; `origin` names it in errors. Pure.
KeyFileResult parse_key_file(std::string_view text, std::string_view origin);

// Reads and parses the key file at `path` after checking that it is a regular file owned by this
// process's user and not accessible by group or others.
KeyFileResult load_key_file(const std::string& path);

}  // namespace meter::protocol
