// Stream reassembly (TCP) on plain bytes: frames split at every possible point, garbage handling.
#include <gtest/gtest.h>

#include <random>

#include "meter/protocol/wire.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

std::vector<std::uint8_t> three_frames() {
  std::vector<std::uint8_t> s;
  encode(Frame{1, 10, Hello{Role::Publisher, kProtocolVersion, 5, 26, 100, "ctl", "ctl.vss.json", 0}}, s);
  encode(Frame{2, 20, Snapshot{true, {{sig::kSpeed, SignalStatus::Valid, 12.0, true, "txt"}}}}, s);
  encode(Frame{3, 30, Heartbeat{}}, s);
  return s;
}

std::vector<std::uint64_t> drain(StreamAssembler& a) {
  std::vector<std::uint64_t> seqs;
  while (auto r = a.next()) {
    EXPECT_EQ(r->error, DecodeError::None) << r->detail;
    seqs.push_back(r->frame.sequence);
  }
  return seqs;
}

TEST(StreamAssembler, OneByteAtATime) {
  const auto s = three_frames();
  StreamAssembler a;
  std::vector<std::uint64_t> seqs;
  for (std::uint8_t b : s) {
    a.append(std::span(&b, 1));
    for (auto q : drain(a)) seqs.push_back(q);
  }
  EXPECT_EQ(seqs, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(a.buffered(), 0U);
}

TEST(StreamAssembler, EveryTwoPieceSplit) {
  const auto s = three_frames();
  for (std::size_t cut = 0; cut <= s.size(); ++cut) {
    StreamAssembler a;
    a.append(std::span(s).first(cut));
    auto seqs = drain(a);
    a.append(std::span(s).subspan(cut));
    for (auto q : drain(a)) seqs.push_back(q);
    EXPECT_EQ(seqs, (std::vector<std::uint64_t>{1, 2, 3})) << "cut " << cut;
  }
}

TEST(StreamAssembler, RandomChunks) {
  std::vector<std::uint8_t> s;
  for (int i = 0; i < 50; ++i) {
    const auto f = three_frames();
    s.insert(s.end(), f.begin(), f.end());
  }
  std::mt19937 rng(7);
  StreamAssembler a;
  std::size_t pos = 0, frames = 0;
  while (pos < s.size()) {
    const std::size_t n = std::min<std::size_t>(s.size() - pos, rng() % 97 + 1);
    a.append(std::span(s).subspan(pos, n));
    pos += n;
    frames += drain(a).size();
  }
  EXPECT_EQ(frames, 150U);
}

TEST(StreamAssembler, MalformedFrameWithGoodCrcIsSkippedAndTheStreamContinues) {
  std::vector<std::uint8_t> s = test::raw_frame(3, {0, 0, 1, 0});  // DELTA count 1, no entry
  const auto unknown = test::raw_frame(42, {1, 2});
  s.insert(s.end(), unknown.begin(), unknown.end());
  encode(Frame{9, 0, Heartbeat{}}, s);
  StreamAssembler a;
  a.append(s);
  auto r1 = a.next();
  ASSERT_TRUE(r1);
  EXPECT_EQ(r1->error, DecodeError::Malformed);
  auto r2 = a.next();
  ASSERT_TRUE(r2);
  EXPECT_EQ(r2->error, DecodeError::UnknownType);
  auto r3 = a.next();
  ASSERT_TRUE(r3);
  EXPECT_EQ(r3->error, DecodeError::None);
  EXPECT_EQ(r3->frame.sequence, 9U);
  EXPECT_FALSE(a.broken());
}

TEST(StreamAssembler, LostFramingBreaksTheStreamOnce) {
  for (auto bad : {DecodeError::BadCrc, DecodeError::BadMagic, DecodeError::BadVersion, DecodeError::Oversized}) {
    std::vector<std::uint8_t> s = encode(Frame{1, 0, Heartbeat{}});
    if (bad == DecodeError::BadCrc) s[28] ^= 1;
    if (bad == DecodeError::BadMagic) s[0] = 'X';
    if (bad == DecodeError::BadVersion) s[4] = 9;
    if (bad == DecodeError::Oversized) s[11] = 0x7F;
    encode(Frame{2, 0, Heartbeat{}}, s);
    StreamAssembler a;
    a.append(s);
    auto r = a.next();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->error, bad);
    EXPECT_TRUE(a.broken());
    EXPECT_FALSE(a.next());  // nothing after the break, even though a good frame followed
    a.append(encode(Frame{3, 0, Heartbeat{}}));
    EXPECT_FALSE(a.next());
    EXPECT_EQ(a.buffered(), 0U);  // and it holds no memory for a stream it will never parse
  }
}

TEST(StreamAssembler, WaitsForAPartialHeaderWithoutError) {
  const auto f = encode(Frame{1, 0, Heartbeat{}});
  StreamAssembler a;
  a.append(std::span(f).first(kHeaderSize - 1));
  EXPECT_FALSE(a.next());
  EXPECT_FALSE(a.broken());
}

}  // namespace
}  // namespace meter::protocol
