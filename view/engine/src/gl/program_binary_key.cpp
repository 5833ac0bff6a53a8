#include "meter/engine/gl/program_binary_key.hpp"

#include <sodium.h>

namespace meter::engine {

namespace {

// Bumped when what goes into the key changes: every binary kept before is then a miss.
constexpr std::string_view kKeyVersion = "meter program binary key 1";

void add_field(crypto_generichash_state& state, std::string_view field) {
  std::array<unsigned char, 8> length{};
  std::uint64_t n = field.size();
  for (auto& b : length) b = static_cast<unsigned char>(n & 0xff), n >>= 8;
  crypto_generichash_update(&state, length.data(), length.size());
  crypto_generichash_update(&state, reinterpret_cast<const unsigned char*>(field.data()), field.size());
}

}  // namespace

ProgramBinaryKey program_binary_key(const DriverIdentity& driver, std::string_view vertex_source,
                                    std::string_view fragment_source) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, nullptr, 0, sizeof(ProgramBinaryKey));
  for (std::string_view field : {kKeyVersion, std::string_view(driver.vendor), std::string_view(driver.renderer),
                                 std::string_view(driver.version), vertex_source, fragment_source})
    add_field(state, field);
  ProgramBinaryKey key{};
  crypto_generichash_final(&state, key.data(), key.size());
  return key;
}

std::string program_binary_file_name(const ProgramBinaryKey& key) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string name;
  name.reserve(key.size() * 2 + 6);
  for (const std::uint8_t b : key) name += kHex[b >> 4], name += kHex[b & 0xf];
  return name + ".glbin";
}

}  // namespace meter::engine
