#include "meter/engine/gl/program_binary_file.hpp"

#include <sodium.h>

#include <algorithm>
#include <array>
#include <cstring>

namespace meter::engine {

namespace {

constexpr char kMagic[8] = {'M', 'E', 'T', 'E', 'R', 'P', 'G', 'B'};
constexpr std::uint32_t kFileVersion = 1;
using Digest = std::array<std::uint8_t, 32>;
constexpr std::size_t kHeaderSize = sizeof kMagic + 4 + 4 + sizeof(ProgramBinaryKey) + sizeof(Digest) + 8;

Digest digest_of(std::span<const std::uint8_t> bytes) {
  Digest d{};
  crypto_generichash(d.data(), d.size(), bytes.data(), bytes.size(), nullptr, 0);
  return d;
}

void put_le(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint64_t get_le(std::span<const std::uint8_t> in, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= std::uint64_t(in[at + static_cast<std::size_t>(i)]) << (8 * i);
  return v;
}

}  // namespace

std::vector<std::uint8_t> encode_program_binary(const ProgramBinaryKey& key, const ProgramBinary& binary) {
  std::vector<std::uint8_t> out(kMagic, kMagic + sizeof kMagic);
  out.reserve(kHeaderSize + binary.bytes.size());
  put_le(out, kFileVersion, 4);
  put_le(out, binary.format, 4);
  out.insert(out.end(), key.begin(), key.end());
  const Digest d = digest_of(binary.bytes);
  out.insert(out.end(), d.begin(), d.end());
  put_le(out, binary.bytes.size(), 8);
  out.insert(out.end(), binary.bytes.begin(), binary.bytes.end());
  return out;
}

DecodedProgramBinary decode_program_binary(std::span<const std::uint8_t> file, const ProgramBinaryKey& key) {
  auto refuse = [](std::string why) { return DecodedProgramBinary{std::nullopt, std::move(why)}; };
  if (file.size() < kHeaderSize)
    return refuse("truncated: " + std::to_string(file.size()) + " bytes, the header needs " + std::to_string(kHeaderSize));
  if (std::memcmp(file.data(), kMagic, sizeof kMagic) != 0) return refuse("not a meter program binary (no METERPGB at offset 0)");
  std::size_t at = sizeof kMagic;
  if (const auto v = get_le(file, at, 4); v != kFileVersion)
    return refuse("file version " + std::to_string(v) + " at offset 8, expected " + std::to_string(kFileVersion));
  at += 4;
  ProgramBinary binary;
  binary.format = static_cast<std::uint32_t>(get_le(file, at, 4));
  at += 4;
  if (!std::equal(key.begin(), key.end(), file.begin() + static_cast<std::ptrdiff_t>(at)))
    return refuse("stored for another driver or other sources (the key at offset 16 differs)");
  at += key.size();
  Digest stored{};
  std::copy_n(file.begin() + static_cast<std::ptrdiff_t>(at), stored.size(), stored.begin());
  at += stored.size();
  const std::uint64_t length = get_le(file, at, 8);
  at += 8;
  if (length != file.size() - at)
    return refuse("the header at offset 80 says " + std::to_string(length) + " bytes of binary, the file holds " +
                  std::to_string(file.size() - at));
  const auto bytes = file.subspan(at);
  if (digest_of(bytes) != stored) return refuse("the binary does not match its digest (damaged)");
  binary.bytes.assign(bytes.begin(), bytes.end());
  return {std::move(binary), {}};
}

}  // namespace meter::engine
