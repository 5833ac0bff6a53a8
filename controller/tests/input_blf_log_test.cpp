#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "meter/controller/input/blf_log.hpp"
#include "meter/controller/input/blf_log_writer.hpp"

using namespace meter::controller;

namespace {

void le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

// One object with a version 1 header, times in nanoseconds, padded as Vector pads.
std::string object(std::uint32_t type, std::uint64_t time_ns, const std::string& payload) {
  std::string o = "LOBJ";
  const std::uint32_t size = 32 + static_cast<std::uint32_t>(payload.size());
  le(o, 32, 2), le(o, 1, 2), le(o, size, 4), le(o, type, 4), le(o, 2, 4), le(o, 0, 4), le(o, time_ns, 8);
  return o + payload + std::string(size % 4, '\0');
}

std::string can_message(std::uint16_t channel, std::uint32_t id, std::uint8_t dlc, std::uint8_t first_byte) {
  std::string p;
  le(p, channel, 2);
  p += '\0';
  p += static_cast<char>(dlc);
  le(p, id, 4);
  p += static_cast<char>(first_byte);
  p.append(7, '\x22');
  return p;
}

// An uncompressed log container around `inner`.
std::string container(const std::string& inner) {
  std::string c = "LOBJ";
  const std::uint32_t size = 32 + static_cast<std::uint32_t>(inner.size());
  le(c, 16, 2), le(c, 1, 2), le(c, size, 4), le(c, kBlfLogContainer, 4), le(c, 0, 2);
  c.append(6, '\0');
  le(c, inner.size(), 4);
  c.append(4, '\0');
  return c + inner + std::string(size % 4, '\0');
}

std::string file_header() {  // no start date: object times from 0
  std::string h = "LOGG";
  le(h, kBlfFileHeaderSize, 4);
  return h + std::string(kBlfFileHeaderSize - 8, '\0');
}

ParsedLog read(const std::string& bytes) {
  std::istringstream in(bytes);
  return read_blf_log(in);
}

ParsedLog sample() {
  ParsedLog log;
  for (int i = 0; i < 3000; ++i) {
    CanFrame f;
    f.timestamp_ns = 1631416514717133000LL + i * 1000123LL;
    f.id = static_cast<std::uint32_t>(0x100 + i % 50);
    f.extended = i % 7 == 0;
    f.channel = static_cast<std::uint8_t>(1 + i % 2);
    f.len = static_cast<std::uint8_t>(i % 9);
    for (int b = 0; b < f.len; ++b) f.data[static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(i + b);
    if (i % 100 == 5) f.rtr = true, f.len = 3, f.data = {};
    if (i % 100 == 6) f.fd = true, f.fd_flags = kCanFdBrs, f.len = 48, f.data.fill(0x5A);
    if (i % 100 == 7) f = CanFrame{f.timestamp_ns, 0, false, false, true, false, 0, 0, 0, 0, 2, {}};
    log.frames.push_back(f);
  }
  return log;
}

}  // namespace

TEST(BlfLog, UnknownObjectsAreCountedAndAnObjectMayContinueInTheNextContainer) {
  const std::string inner = object(kBlfCanMessage, 1000, can_message(1, 0x123, 2, 0xAB)) +
                            object(65, 2000, std::string(20, 'x')) +  // APP_TEXT: no frame
                            object(kBlfCanMessage2, 3000, can_message(2, 0x80000000u | 0x1234567, 8, 0xCD) + std::string(8, '\0')) +
                            object(kBlfCanErrorExt, 4000, std::string(32, '\0').replace(0, 1, "\x03"));
  const std::size_t cut = 60;  // inside the second object
  const ParsedLog log = read(file_header() + container(inner.substr(0, cut)) + container(inner.substr(cut)));
  ASSERT_TRUE(log.bad_lines.empty()) << log.bad_lines.front().why;
  EXPECT_EQ(log.skipped, 1u);
  ASSERT_EQ(log.frames.size(), 3u);
  EXPECT_EQ(log.frames[0].timestamp_ns, 1000);
  EXPECT_EQ(log.frames[0].id, 0x123u);
  EXPECT_EQ(log.frames[0].len, 2);
  EXPECT_EQ(log.frames[0].data[0], 0xAB);
  EXPECT_TRUE(log.frames[1].extended);
  EXPECT_EQ(log.frames[1].id, 0x1234567u);
  EXPECT_EQ(log.frames[1].channel, 2);
  EXPECT_TRUE(log.frames[2].error);
  EXPECT_EQ(log.frames[2].channel, 3);
  EXPECT_TRUE(sniff_blf_log(file_header()));
}

TEST(BlfLog, TheWriterWritesWhatTheReaderReadsBack) {
  const ParsedLog log = sample();
  std::stringstream out;
  ParsedLogSource frames(log);
  write_blf_log(frames, out, [](std::size_t) {});
  const ParsedLog back = read(out.str());
  ASSERT_TRUE(back.bad_lines.empty()) << back.bad_lines.front().why;
  ASSERT_EQ(back.frames.size(), log.frames.size());
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    const CanFrame &a = log.frames[i], &b = back.frames[i];
    ASSERT_TRUE(a.timestamp_ns == b.timestamp_ns && a.id == b.id && a.extended == b.extended && a.rtr == b.rtr &&
                a.error == b.error && a.fd == b.fd && a.fd_flags == b.fd_flags && a.len == b.len && a.channel == b.channel &&
                (a.rtr || std::equal(a.data.begin(), a.data.begin() + a.len, b.data.begin())))
        << "frame " << i;
  }
}

// Every cut of the file and a damaged zlib block: a bad record with the byte offset and the
// object, never a crash, and every frame before the damage kept.
TEST(BlfLog, ATruncatedFileOrACorruptContainerKeepsTheFramesBeforeTheDamage) {
  const ParsedLog log = sample();
  std::stringstream out;
  ParsedLogSource frames(log);
  write_blf_log(frames, out, [](std::size_t) {});
  const std::string bytes = out.str();
  std::vector<std::size_t> ends;  // where a cut leaves whole containers only: no damage to report
  for (std::size_t pos = kBlfFileHeaderSize; pos + 12 <= bytes.size();) {
    const auto size = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[pos + 8]) | static_cast<unsigned char>(bytes[pos + 9]) << 8 |
                                                 static_cast<unsigned char>(bytes[pos + 10]) << 16);
    pos += size + size % 4;
    ends.push_back(pos);
  }
  ASSERT_GE(ends.size(), 2u);
  std::size_t last = 0;
  for (std::size_t cut = 0; cut < bytes.size(); cut += 97) {
    const ParsedLog part = read(bytes.substr(0, cut));
    ASSERT_GE(part.frames.size(), last) << cut;
    ASSERT_LE(part.frames.size(), log.frames.size());
    last = part.frames.size();
    if (cut > kBlfFileHeaderSize && std::find(ends.begin(), ends.end(), cut) == ends.end()) {
      ASSERT_EQ(part.bad_lines.size(), 1u) << cut;
      EXPECT_NE(part.bad_lines[0].why.find("byte offset"), std::string::npos) << part.bad_lines[0].why;
    }
  }
  std::string damaged = bytes;
  damaged[kBlfFileHeaderSize + 40] ^= 0x55;  // inside the first container's zlib data
  const ParsedLog broken = read(damaged);
  ASSERT_EQ(broken.bad_lines.size(), 1u);
  EXPECT_NE(broken.bad_lines[0].why.find("byte offset 144 (object 1, LOG_CONTAINER): corrupt zlib data"), std::string::npos)
      << broken.bad_lines[0].why;
  const std::size_t second = bytes.find("LOBJ", kBlfFileHeaderSize + 4);  // the second container
  ASSERT_NE(second, std::string::npos);
  damaged = bytes;
  damaged[second + 60] ^= 0x55;
  const ParsedLog half = read(damaged);
  ASSERT_EQ(half.bad_lines.size(), 1u);
  EXPECT_NE(half.bad_lines[0].why.find("byte offset " + std::to_string(second)), std::string::npos) << half.bad_lines[0].why;
  EXPECT_GT(half.frames.size(), 1000u);  // the first container's frames
  EXPECT_NE(read("LOGX").bad_lines.at(0).why.find("expected the BLF signature 'LOGG'"), std::string::npos);
}
