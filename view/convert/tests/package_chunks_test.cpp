// The package's framing (meter/bridge/package_format.hpp): tagged, length-prefixed chunks. A chunk
// the reader does not know is skipped and noted; a required one missing, a length past the end, a
// chunk twice or a section with bytes left over is an error naming the chunk and offset; a package
// of the older fixed-order formats, or a chunk written with other field lists, is refused with the
// command that reconverts it.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "every_section_scene.hpp"
#include "meter/bridge/package_format.hpp"
#include "meter/bridge/package_schema.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"

using namespace meter;
using namespace meter::convert;

namespace {

using Bytes = std::vector<std::uint8_t>;

struct RawChunk {
  std::string tag;
  Bytes body;
  std::uint64_t schema = 0;
};

std::vector<RawChunk> chunks_of(const Bytes& package) {
  std::vector<RawChunk> out;
  for (std::size_t pos = kPackageHeaderSize; pos < package.size();) {
    std::uint64_t schema = 0, n = 0;
    std::memcpy(&schema, package.data() + pos + 4, 8);
    std::memcpy(&n, package.data() + pos + 12, 8);
    out.push_back({std::string(package.begin() + long(pos), package.begin() + long(pos) + 4),
                   Bytes(package.begin() + long(pos + kChunkHeaderSize), package.begin() + long(pos + kChunkHeaderSize + n)), schema});
    pos += kChunkHeaderSize + n;
  }
  return out;
}

template <class T>
void put(Bytes& b, T v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof v);
}

// A package of these chunks, its header's size and checksum matching (`length_bias` added to the
// last chunk's stated length).
Bytes package_of(const std::vector<RawChunk>& chunks, std::uint32_t version = kPackageVersion, std::uint64_t length_bias = 0) {
  Bytes payload;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    payload.insert(payload.end(), chunks[i].tag.begin(), chunks[i].tag.end());
    put<std::uint64_t>(payload, chunks[i].schema);
    put<std::uint64_t>(payload, chunks[i].body.size() + (i + 1 == chunks.size() ? length_bias : 0));
    payload.insert(payload.end(), chunks[i].body.begin(), chunks[i].body.end());
  }
  Bytes out(std::begin(kPackageMagic), std::end(kPackageMagic));
  put(out, version);
  put(out, std::uint32_t{0});
  put<std::uint64_t>(out, payload.size());
  put(out, package_checksum(payload));
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

std::string load_error(const Bytes& b, engine::PackageNotes* notes = nullptr) {
  engine::PackageNotes local;
  try {
    engine::deserialize_scene(b, "p.msp", notes ? notes : &local);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

const Bytes& written() {
  static const Bytes b = serialize_scene(meter::convert::test::every_section());
  return b;
}

}  // namespace

TEST(PackageChunks, TheWriterWritesOneChunkPerSection) {
  std::vector<std::string> tags;
  for (const auto& c : chunks_of(written())) tags.push_back(c.tag);
  EXPECT_EQ(tags, (std::vector<std::string>{"SRCN", "NODE", "ROOT", "MESH", "MATL", "TEXR", "CAMR", "LGHT", "SKIN", "ANIM",
                                            "PROG", "DRAW", "GRUP", "ENVR", "CONF", "INTG", "LEVL", "FONT"}));
  EXPECT_EQ(package_of(chunks_of(written())), written());
}

TEST(PackageChunks, AnUnknownChunkIsSkippedAndNoted) {
  auto chunks = chunks_of(written());
  chunks.insert(chunks.begin() + 3, RawChunk{"XTRA", Bytes(12, 7)});
  engine::PackageNotes notes;
  ASSERT_EQ(load_error(package_of(chunks), &notes), "");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("skipped chunk 'XTRA' (12 bytes at byte "), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("not a section this build knows"), std::string::npos) << notes[0];
}

TEST(PackageChunks, ChunksReadInAnyOrder) {
  auto chunks = chunks_of(written());
  std::swap(chunks[1], chunks[10]);
  EXPECT_EQ(load_error(package_of(chunks)), "");
}

TEST(PackageChunks, AMissingRequiredChunkIsNamed) {
  auto chunks = chunks_of(written());
  std::erase_if(chunks, [](const RawChunk& c) { return c.tag == "DRAW"; });
  EXPECT_NE(load_error(package_of(chunks)).find("no chunk DRAW (draws), which every package has"), std::string::npos)
      << load_error(package_of(chunks));
  // An optional section may be left out: the scene has none of it.
  auto without_groups = chunks_of(written());
  std::erase_if(without_groups, [](const RawChunk& c) { return c.tag == "GRUP"; });
  EXPECT_EQ(load_error(package_of(without_groups)), "");
}

TEST(PackageChunks, APackageWithTextsButNoFontChunkIsRefusedNamingThePackage) {
  // Texts are drawn from the package's font only: without its FONT chunk (a package written
  // before the font travelled with the scene) the load fails, naming the package and the chunk.
  Scene s = meter::convert::test::every_section();
  s.config.source_json = R"({"format": "meter-scene-config/1", "link_loss": {"text_node": "Quad"}})";
  auto chunks = chunks_of(serialize_scene(s));
  EXPECT_EQ(load_error(package_of(chunks)), "");
  std::erase_if(chunks, [](const RawChunk& c) { return c.tag == "FONT"; });
  const std::string e = load_error(package_of(chunks));
  EXPECT_NE(e.find("p.msp: the scene draws text but the package has no chunk FONT (font)"), std::string::npos) << e;
  EXPECT_NE(e.find("reconvert it with this build's converter"), std::string::npos) << e;
  // A scene without text needs no font: its package loads without the chunk.
  auto plain = chunks_of(written());
  std::erase_if(plain, [](const RawChunk& c) { return c.tag == "FONT"; });
  EXPECT_EQ(load_error(package_of(plain)), "");
}

TEST(PackageChunks, ALengthPastTheEndNamesTheChunkAndOffset) {
  const auto chunks = chunks_of(written());
  const std::string e = load_error(package_of(chunks, kPackageVersion, 1));
  EXPECT_NE(e.find("corrupt package at byte "), std::string::npos) << e;
  EXPECT_NE(e.find("chunk 'FONT' says "), std::string::npos) << e;  // the last chunk
  EXPECT_NE(e.find(" follow it"), std::string::npos) << e;
  auto twice = chunks;
  twice.push_back(chunks[2]);
  EXPECT_NE(load_error(package_of(twice)).find("chunk 'ROOT' appears twice"), std::string::npos);
}

TEST(PackageChunks, ASectionMustUseItsChunkExactly) {
  auto chunks = chunks_of(written());
  chunks[2].body.push_back(0);  // ROOT
  EXPECT_NE(load_error(package_of(chunks)).find("(chunk ROOT): roots: bytes left over after the section"), std::string::npos)
      << load_error(package_of(chunks));
  chunks[2].body.resize(2);
  EXPECT_NE(load_error(package_of(chunks)).find("(chunk ROOT): roots: truncated"), std::string::npos) << load_error(package_of(chunks));
}

TEST(PackageChunks, ABadFieldIsNamedByItsPath) {
  auto s = meter::convert::test::every_section();
  s.programs[0].program.samplers[0].unit = 99;
  const std::string e = load_error(serialize_scene(s));
  EXPECT_NE(e.find("(chunk PROG): programs[0].program.samplers[0]: sampler unit out of range"), std::string::npos) << e;
}

// A chunk written with other field lists (a converter before a field was added to programs, say)
// is refused with the reconvert command, never misread.
TEST(PackageChunks, AChunkOfOtherFieldListsIsRefusedWithTheReconvertCommand) {
  auto chunks = chunks_of(written());
  ASSERT_EQ(chunks[10].tag, "PROG");
  chunks[10].schema ^= 1;
  const std::string e = load_error(package_of(chunks));
  EXPECT_NE(e.find("p.msp: chunk PROG (programs, at byte "), std::string::npos) << e;
  EXPECT_NE(e.find(") was written with other field lists than this build's"), std::string::npos) << e;
  EXPECT_NE(e.find("reconvert it with this build's converter: meter-convert hand-built --config SCENE.json -o p.msp"),
            std::string::npos) << e;
}

// A section's schema is that of its field lists: every list of records has its own (the two
// texts, source name and config, share theirs), whatever the contents.
TEST(PackageChunks, SchemasFollowTheFieldLists) {
  std::set<std::uint64_t> schemas;
  for (const auto& c : chunks_of(written())) {
    if (c.tag != "CONF") {
      EXPECT_TRUE(schemas.insert(c.schema).second) << c.tag;
    }
  }
  EXPECT_NE(bridge::section_schema(std::vector<bridge::DrawItem>{}), bridge::section_schema(std::vector<bridge::MergedGroup>{}));
  EXPECT_EQ(bridge::section_schema(std::vector<bridge::DrawItem>{}), bridge::section_schema(std::vector<bridge::DrawItem>(3)));
}

// Formats up to 7 were one fixed-order layout behind the same header: refused, with the command
// that reconverts the package (its source named from the old payload, which began with it).
TEST(PackageChunks, AnOlderFormatIsRefusedWithTheReconvertCommand) {
  Bytes old_payload;
  const std::string source = "scenes/cluster/cluster.glb";
  put<std::uint32_t>(old_payload, std::uint32_t(source.size()));
  old_payload.insert(old_payload.end(), source.begin(), source.end());
  old_payload.resize(old_payload.size() + 40, 0);
  Bytes old(std::begin(kPackageMagic), std::end(kPackageMagic));
  put(old, std::uint32_t{7});
  put(old, std::uint32_t{0});
  put<std::uint64_t>(old, old_payload.size());
  put(old, package_checksum(old_payload));
  old.insert(old.end(), old_payload.begin(), old_payload.end());
  const std::string e = load_error(old);
  EXPECT_NE(e.find("p.msp: scene package format version 7 is older than the tagged chunks this build reads (version 8)"),
            std::string::npos) << e;
  EXPECT_NE(e.find("reconvert it with this build's converter: meter-convert scenes/cluster/cluster.glb --config SCENE.json -o p.msp"),
            std::string::npos) << e;
}
