// The link key file: its grammar (pure) and the ownership and mode checks before it is read.
#include "meter/protocol/key_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sodium.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>

#include "transport/unique_fd.hpp"

namespace meter::protocol {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// One "<id> <hex>" line into `key`; "" or what was wrong.
std::string parse_line(std::string_view line, LinkKey& key) {
  const auto space = line.find_first_of(" \t");
  if (space == std::string_view::npos) return "expected '<key id> <64 hex digits>', got one field";
  const auto id_text = line.substr(0, space);
  const auto hex = trim(line.substr(space));
  const auto* end = id_text.data() + id_text.size();
  const auto r = std::from_chars(id_text.data(), end, key.id);
  if (r.ec != std::errc() || r.ptr != end || key.id == 0) {
    return "key id '" + std::string(id_text) + "': expected an integer 1..4294967295";
  }
  if (hex.size() != 2 * kLinkKeySize) {
    return "key " + std::to_string(key.id) + ": expected " + std::to_string(2 * kLinkKeySize) +
           " hex digits (a 256-bit key), got " + std::to_string(hex.size()) + " characters";
  }
  // libsodium's decoder takes time independent of the digits (a key's bytes do not show in timing).
  const char* stop = nullptr;
  std::size_t decoded = 0;
  if (sodium_hex2bin(key.key.bytes.data(), key.key.bytes.size(), hex.data(), hex.size(), nullptr, &decoded, &stop) != 0 ||
      decoded != kLinkKeySize) {
    // The decoder stops at a pair it cannot finish: the bad digit is its first or its second.
    auto at = static_cast<std::size_t>(stop - hex.data());
    if (at < hex.size() && std::isxdigit(static_cast<unsigned char>(hex[at]))) ++at;
    ++at;  // counted from 1
    return "key " + std::to_string(key.id) + ": character " + std::to_string(at) + " of the key is not a hex digit";
  }
  if (sodium_is_zero(key.key.bytes.data(), key.key.bytes.size()) == 1) {
    return "key " + std::to_string(key.id) + " is all zeros (not a key: generate one, docs/security.md)";
  }
  return {};
}

}  // namespace

KeyFileResult parse_key_file(std::string_view text, std::string_view origin) {
  KeyFileResult out;
  const auto fail = [&](std::size_t line, const std::string& what) {
    out.keys.clear();
    out.error = std::string(origin) + ":" + std::to_string(line) + ": " + what;
    return out;
  };
  if (text.size() > kMaxKeyFileBytes) {
    return fail(1, "the file has " + std::to_string(text.size()) + " bytes, a key file at most " +
                       std::to_string(kMaxKeyFileBytes));
  }
  std::size_t line_no = 0;
  while (!text.empty()) {
    ++line_no;
    const auto nl = text.find('\n');
    const auto line = trim(text.substr(0, nl));
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    if (line.empty() || line.front() == '#') continue;
    LinkKey key;
    if (auto why = parse_line(line, key); !why.empty()) return fail(line_no, why);
    if (std::any_of(out.keys.begin(), out.keys.end(), [&](const LinkKey& k) { return k.id == key.id; })) {
      return fail(line_no, "key id " + std::to_string(key.id) + " appears twice");
    }
    out.keys.push_back(key);
  }
  if (out.keys.empty()) return fail(line_no == 0 ? 1 : line_no, "no key: expected a line '<key id> <64 hex digits>'");
  return out;
}

KeyFileResult load_key_file(const std::string& path) {
  KeyFileResult out;
  detail::UniqueFd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW));
  if (!fd) {
    out.error = path + ": cannot open the key file: " + std::strerror(errno);
    return out;
  }
  struct stat st{};
  if (::fstat(fd.get(), &st) != 0 || !S_ISREG(st.st_mode)) {
    out.error = path + ": the key file is not a regular file";
    return out;
  }
  if (st.st_uid != ::geteuid()) {
    out.error = path + ": the key file belongs to uid " + std::to_string(st.st_uid) + ", this process runs as uid " +
                std::to_string(::geteuid());
    return out;
  }
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    out.error = path + ": the key file has mode " + mode +
                ": group or others may access it; expected 0600 (chmod 600 " + path + ")";
    return out;
  }
  std::string text(kMaxKeyFileBytes + 1, '\0');
  std::size_t got = 0;
  for (;;) {
    const ssize_t n = ::read(fd.get(), text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      out.error = path + ": cannot read the key file: " + std::strerror(errno);
      return out;
    }
    if (n == 0 || (got += static_cast<std::size_t>(n)) == text.size()) break;
  }
  text.resize(got);
  auto parsed = parse_key_file(text, path);
  sodium_memzero(text.data(), text.size());  // the keys' text does not outlive the read in freed memory
  return parsed;
}

}  // namespace meter::protocol
