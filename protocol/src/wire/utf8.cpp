// UTF-8 for the text fields: the strict validator the decoder applies, and the sanitizer the
// Publisher applies to whatever text a caller passes.
#include <algorithm>
#include <cstdint>
#include <string>

#include "meter/protocol/wire.hpp"
#include "wire/utf8.hpp"

namespace meter::protocol {

bool is_valid_utf8(std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  std::size_t i = 0;
  const std::size_t n = text.size();
  while (i < n) {
    const unsigned char c = s[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    std::uint32_t cp = 0;
    if ((c & 0xE0) == 0xC0) {
      len = 2;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      len = 3;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      len = 4;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + len > n) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((s[i + k] & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (s[i + k] & 0x3F);
    }
    // Reject overlong forms, surrogates and code points past U+10FFFF.
    if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000)) return false;
    if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return false;
    i += len;
  }
  return true;
}

namespace detail {

std::string sanitize_text(std::string_view text) {
  std::string out;
  out.reserve(std::min(text.size(), kMaxTextBytes));
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t len = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    std::string_view ch = "?";
    std::size_t advance = 1;  // an invalid byte becomes '?' and we resync on the next byte
    if (len != 0 && i + len <= text.size() && is_valid_utf8(text.substr(i, len))) {
      ch = text.substr(i, len);
      advance = len;
    }
    if (out.size() + ch.size() > kMaxTextBytes) break;
    out.append(ch);
    i += advance;
  }
  return out;
}

}  // namespace detail
}  // namespace meter::protocol
