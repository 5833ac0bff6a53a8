// The package reader: the header, the chunk directory and each section decoded by its records'
// field lists (record_decoder.hpp), then the references between sections (scene_references.hpp).
#include "meter/engine/package_reader.hpp"

#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>

#include "meter/bridge/package_schema.hpp"
#include "meter/platform/text.hpp"
#include "record_decoder.hpp"
#include "scene_references.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::engine {
namespace {

struct Chunk {
  std::uint64_t schema;
  std::span<const std::uint8_t> body;
  std::size_t offset;  // of the body, from the start of the file
};

template <class T>
T load(std::span<const std::uint8_t> bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

std::string printable_tag(std::span<const std::uint8_t> tag) {
  std::string t;
  for (std::uint8_t c : tag) t += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
  return "'" + t + "'";
}

// The source glTF an older package names first in its payload (every format up to 7 began with it),
// for the reconvert command; "SCENE.glb" when it cannot be read.
std::string old_source_name(std::span<const std::uint8_t> payload) {
  if (payload.size() < 4) return "SCENE.glb";
  const auto n = load<std::uint32_t>(payload, 0);
  if (n == 0 || n > payload.size() - 4 || n > 4096) return "SCENE.glb";
  return std::string(reinterpret_cast<const char*>(payload.data() + 4), n);
}

std::string reconvert(const std::string& source, const std::string& origin) {
  return "reconvert it with this build's converter: meter-convert " + source + " --config SCENE.json -o " + origin;
}

// The header checked (magic, version, size, checksum); returns the payload.
std::span<const std::uint8_t> payload_of(std::span<const std::uint8_t> bytes, const std::string& origin) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kPackageMagic, 8) != 0) {
    throw SceneError(origin + ": not a meter scene package (bad magic; expected \"METERSCN\" — convert the "
                     "glTF with meter-convert first)");
  }
  if (bytes.size() < kPackageHeaderSize) throw SceneError(origin + ": truncated package header");
  const auto version = load<std::uint32_t>(bytes, 8);
  const auto size = load<std::uint64_t>(bytes, 16);
  const auto hash = load<std::uint64_t>(bytes, 24);
  const auto payload = bytes.subspan(kPackageHeaderSize);
  if (version < kPackageVersion) {
    throw SceneError(origin + ": scene package format version " + std::to_string(version) +
                     " is older than the tagged chunks this build reads (version " + std::to_string(kPackageVersion) +
                     "); " + reconvert(old_source_name(payload), origin));
  }
  if (version != kPackageVersion) {
    throw SceneError(origin + ": scene package format version " + std::to_string(version) +
                     " is not supported by this build (it reads version " + std::to_string(kPackageVersion) +
                     "); re-run meter-convert on the source glTF");
  }
  if (size != payload.size()) {
    throw SceneError(origin + ": package payload is " + std::to_string(payload.size()) + " bytes but the header says " +
                     std::to_string(size) + " (truncated or padded file)");
  }
  if (package_checksum(payload) != hash) throw SceneError(origin + ": package checksum mismatch (file corrupted)");
  return payload;
}

// The chunks by tag. A length past the payload's end, or a tag twice, is an error naming the chunk
// and its offset.
std::map<std::string, Chunk> chunks_of(std::span<const std::uint8_t> payload, const std::string& origin) {
  std::map<std::string, Chunk> chunks;
  std::size_t pos = 0;
  while (pos < payload.size()) {
    const std::size_t at = kPackageHeaderSize + pos;
    if (payload.size() - pos < kChunkHeaderSize)
      throw SceneError(origin + ": corrupt package at byte " + std::to_string(at) + ": truncated chunk header (" +
                       std::to_string(payload.size() - pos) + " bytes left, a chunk header is " + std::to_string(kChunkHeaderSize) + ")");
    const auto tag = payload.subspan(pos, 4);
    const auto schema = load<std::uint64_t>(payload, pos + 4);
    const auto length = load<std::uint64_t>(payload, pos + 12);
    const std::size_t left = payload.size() - pos - kChunkHeaderSize;
    if (length > left)
      throw SceneError(origin + ": corrupt package at byte " + std::to_string(at) + ": chunk " + printable_tag(tag) + " says " +
                       std::to_string(length) + " bytes but " + std::to_string(left) + " follow it");
    const std::string key(tag.begin(), tag.end());
    if (!chunks.emplace(key, Chunk{schema, payload.subspan(pos + kChunkHeaderSize, length), at + kChunkHeaderSize}).second)
      throw SceneError(origin + ": corrupt package at byte " + std::to_string(at) + ": chunk " + printable_tag(tag) + " appears twice");
    pos += kChunkHeaderSize + length;
  }
  return chunks;
}

}  // namespace

Scene deserialize_scene(std::span<const std::uint8_t> bytes, const std::string& origin, PackageNotes* notes) {
  auto chunks = chunks_of(payload_of(bytes, origin), origin);
  Scene s;
  bridge::fields(s, [&](const bridge::SceneSection& section, auto& member) {
    const auto it = chunks.find(section.tag);
    if (it == chunks.end()) {
      if (section.required)
        throw SceneError(origin + ": corrupt package: no chunk " + section.tag + " (" + section.name + "), which every package has");
      return;
    }
    if (it->second.schema != bridge::section_schema(member))
      throw SceneError(origin + ": chunk " + section.tag + " (" + section.name + ", at byte " +
                       std::to_string(it->second.offset - kChunkHeaderSize) +
                       ") was written with other field lists than this build's (a converter before or after a change of its "
                       "records); " + reconvert(s.source_name.empty() ? "SCENE.glb" : s.source_name, origin));
    RecordDecoder in(it->second.body, it->second.offset, origin, section.tag);
    in.value(section.name, member);
    if (!in.at_end()) in.fail_at(section.name, "bytes left over after the section");
    chunks.erase(it);
  });
  // What is left is newer than this build: skipped, and said so.
  for (const auto& [tag, chunk] : chunks) {
    const std::string note = origin + ": skipped chunk '" + tag + "' (" + std::to_string(chunk.body.size()) + " bytes at byte " +
                             std::to_string(chunk.offset - kChunkHeaderSize) + "): not a section this build knows";
    if (notes) notes->push_back(note);
    else protocol::LogLine(protocol::LogLevel::Info, "package") << "meter: note: " << note;
  }
  check_references(s, origin);
  load_config(s, origin);
  // The texts are drawn from the package's font only: a package written before the font travelled
  // with the scene (or with its FONT chunk removed) is refused here, not at the first text drawn.
  if (!s.font.present() && bridge::config_draws_text(s.config))
    throw SceneError(origin + ": the scene draws text but the package has no chunk FONT (font), the font its texts are "
                     "drawn with; " + reconvert(s.source_name.empty() ? "SCENE.glb" : s.source_name, origin));
  if (s.font.present()) {
    try {
      platform::check_font({s.font.name, s.font.data});
    } catch (const platform::TextError& e) {
      throw SceneError(origin + ": chunk FONT (font): " + e.what());
    }
  }
  return s;
}

Scene read_package(const std::string& path, PackageNotes* notes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open scene package");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return deserialize_scene(bytes, path, notes);
}

}  // namespace meter::engine
