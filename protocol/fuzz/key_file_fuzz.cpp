// Fuzzes the link key file reader (--key-file of both processes) as the link uses it: parse, then
// derive the HELLO and session keys from every key, tag a frame with each and verify the tag. A
// good file written back in the canonical form parses to the same keys. A crash, a sanitizer
// report, an exception, or a broken invariant is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/key_file.hpp"

using namespace meter::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const KeyFileResult r = parse_key_file(text, "fuzz.keys");
  if (!r.error.empty()) {
    if (!r.keys.empty() || r.error.rfind("fuzz.keys:", 0) != 0) std::abort();  // file:line: what
    return 0;
  }
  if (r.keys.empty()) std::abort();  // a good file holds a key
  std::string canonical;
  const Nonce nonce{};
  const auto frame = encode(Frame{1, 0, Heartbeat{}});
  for (const LinkKey& k : r.keys) {
    if (k.id == 0) std::abort();
    canonical += std::to_string(k.id) + " ";
    for (std::uint8_t b : k.key.bytes) {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02x", b);
      canonical += hex;
    }
    canonical += "\n";
    const FrameKey session = derive_session_key(k.key, Role::Publisher, nonce, nonce);
    const auto tagged = encode(Frame{1, 0, Heartbeat{}}, &session);
    if (!frame_tag_matches(tagged, session) || frame_tag_matches(frame, session)) std::abort();
    if (derive_hello_key(k.key, Role::Publisher) == session) std::abort();
  }
  const KeyFileResult again = parse_key_file(canonical, "again.keys");
  if (!again.error.empty() || again.keys.size() != r.keys.size()) std::abort();
  for (std::size_t i = 0; i < r.keys.size(); ++i) {
    if (again.keys[i].id != r.keys[i].id || again.keys[i].key != r.keys[i].key) std::abort();
  }
  return 0;
}
