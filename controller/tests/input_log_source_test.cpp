// Logs are streamed: the replay pulls a frame at a time, so the frames a source holds (its window)
// do not grow with the log's length, in every format and through the merge of several logs; the
// order and the error cases stay as documented (docs/logs.md).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "meter/controller/input/asc_log.hpp"
#include "meter/controller/input/asc_log_writer.hpp"
#include "meter/controller/input/blf_log.hpp"
#include "meter/controller/input/blf_log_writer.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_replay.hpp"
#include "meter/controller/input/merge_logs.hpp"
#include "meter/controller/input/trc_log.hpp"
#include "meter/controller/input/write_log_chunks.hpp"

using namespace meter::controller;

namespace {

struct Counted : InputSink {
  std::vector<std::uint8_t> first_bytes;  // each frame's first data byte, in delivery order
  std::size_t frames = 0;
  void on_frame(const CanFrame& f) override {
    ++frames;
    if (first_bytes.size() < 64) first_bytes.push_back(f.data[0]);
  }
  void on_value(std::string_view, double, bool, std::int64_t) override {}
};

// `n` frames 1 ms apart on two channels, every kind the writers write.
ParsedLog drive(std::size_t n) {
  ParsedLog log;
  for (std::size_t i = 0; i < n; ++i) {
    CanFrame f;
    f.timestamp_ns = 1'600'000'000'000'000'000 + static_cast<std::int64_t>(i) * 1'000'000;
    f.id = 0x100 + static_cast<std::uint32_t>(i % 7);
    f.channel = static_cast<std::uint8_t>(1 + i % 2);
    f.len = 8;
    f.data[0] = static_cast<std::uint8_t>(i);
    f.fd = i % 5 == 0;
    if (f.fd) f.len = 16;
    log.frames.push_back(f);
  }
  return log;
}

// A PCAN trace (version 1.1) of `n` frames: its format has no writer in this build.
std::string trc_text(std::size_t n) {
  std::string t = ";$FILEVERSION=1.1\n";
  for (std::size_t i = 0; i < n; ++i)
    t += std::to_string(i + 1) + ")  " + std::to_string(i) + ".0  Rx  0100  8  " + (i % 2 ? "01" : "02") + " 00 00 00 00 00 00 00\n";
  return t;
}

std::string written(std::size_t (*write)(LogSource&, std::ostream&, const LogProgress&), std::size_t n) {
  std::stringstream out;
  ParsedLogSource frames(drive(n));
  write(frames, out, [](std::size_t) {});
  return out.str();
}

// Replays the log in `bytes` through its format's source (fast, to its end): the frames
// delivered and the most the source held at once.
std::pair<std::size_t, std::size_t> replay(const LogFormat& format, const std::string& bytes) {
  std::istringstream in(bytes);
  LogReplay r(format.open(in), ReplayOptions{ReplayMode::Fast, 1.0, std::chrono::hours(1)});
  Counted sink;
  while (r.poll(sink, std::chrono::milliseconds(0))) {
  }
  EXPECT_EQ(r.source().bad_records(), 0u) << format.name;
  return {sink.frames, r.source().window_peak()};
}

}  // namespace

TEST(LogSource, TheFramesHeldDoNotGrowWithTheLogsLengthInEveryFormat) {
  const struct {
    const LogFormat& format;
    std::string small, large;
  } logs[] = {
      {candump_log_format(), written(write_candump_log, 500), written(write_candump_log, 20000)},
      {asc_log_format(), written(write_asc_log, 500), written(write_asc_log, 20000)},
      {blf_log_format(), written(write_blf_log, 500), written(write_blf_log, 20000)},
      {trc_log_format(), trc_text(500), trc_text(20000)},
  };
  for (const auto& l : logs) {
    const auto [small_frames, small_held] = replay(l.format, l.small);
    const auto [large_frames, large_held] = replay(l.format, l.large);
    EXPECT_EQ(small_frames, 500u) << l.format.name;
    EXPECT_EQ(large_frames, 20000u) << l.format.name;
    // One record read per frame asked: a BLF container's objects are read one at a time too.
    EXPECT_EQ(small_held, 1u) << l.format.name;
    EXPECT_EQ(large_held, 1u) << l.format.name;
  }
}

TEST(LogSource, MergedLogsHoldOneFrameOfEachLog) {
  std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs;
  std::istringstream a(written(write_blf_log, 3000)), b(written(write_candump_log, 2000));
  logs.emplace_back(0, blf_log_format().open(a));
  logs.emplace_back(1, candump_log_format().open(b));
  MergedLogSource merged(std::move(logs));
  std::size_t n = 0;
  std::int64_t last = 0;
  while (const CanFrame* f = merged.next()) {
    EXPECT_GE(f->timestamp_ns, last);
    last = f->timestamp_ns;
    ++n;
  }
  EXPECT_EQ(n, 5000u);
  EXPECT_EQ(merged.window_peak(), 1u);
  for (const auto& [index, log] : merged.logs()) EXPECT_EQ(log->window_peak(), 1u) << index;
}

// A log whose time steps back is replayed in file order: the frame that steps back is already due,
// so it is handed over at once, right after the frame before it.
TEST(LogSource, ALogWhoseTimeStepsBackIsReplayedInFileOrder) {
  LogReplay r(parse_candump_log("(5.000) can0 100#01\n(4.000) can0 100#02\n(5.005) can0 100#03\n(5.030) can0 100#04\n"),
              ReplayOptions{ReplayMode::Fast, 1.0, std::chrono::milliseconds(10)});
  Counted sink;
  r.poll(sink, std::chrono::milliseconds(0));  // up to 5.010 s: the first three
  EXPECT_EQ(sink.first_bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  while (r.poll(sink, std::chrono::milliseconds(0))) {
  }
  EXPECT_EQ(sink.first_bytes, (std::vector<std::uint8_t>{1, 2, 3, 4}));
}

// A bad line in the middle: the frames before and after it are replayed, and it is reported when
// the replay reaches it (with its line number), not before the first frame.
TEST(LogSource, ABadLineInTheMiddleIsReportedWhenReachedAndTheReplayGoesOn) {
  std::istringstream in("(1.000) can0 100#01\n(1.001) can0 100#02\nnot a frame\n(1.003) can0 100#03\n");
  std::unique_ptr<LogSource> source = candump_log_format().open(in);
  std::vector<std::size_t> reported;
  source->on_bad_record([&](const BadLine& b) { reported.push_back(b.line); });
  std::vector<std::uint8_t> got;
  while (const CanFrame* f = source->next()) {
    got.push_back(f->data[0]);
    if (got.size() == 2) {
      EXPECT_TRUE(reported.empty());  // not read yet
    }
  }
  EXPECT_EQ(got, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_EQ(reported, (std::vector<std::size_t>{3}));
  EXPECT_EQ(source->bad_records(), 1u);
}

// A truncated BLF: every frame before the damage is replayed, then the bad record names the byte
// offset, and the replay ends there.
TEST(LogSource, ATruncatedBlfReplaysTheFramesBeforeTheDamage) {
  const std::string whole = written(write_blf_log, 6000);  // several containers
  const std::string cut = whole.substr(0, whole.size() * 2 / 3);
  std::istringstream in(cut);
  LogReplay r(blf_log_format().open(in), ReplayOptions{ReplayMode::Fast, 1.0, std::chrono::hours(1)});
  Counted sink;
  while (r.poll(sink, std::chrono::milliseconds(0))) {
  }
  EXPECT_GT(sink.frames, 1000u);  // the first containers whole
  EXPECT_LT(sink.frames, 6000u);
  ASSERT_EQ(r.source().bad_records(), 1u);
  EXPECT_NE(r.source().records().bad_lines[0].why.find("byte offset"), std::string::npos) << r.source().records().bad_lines[0].why;
  EXPECT_EQ(r.source().window_peak(), 1u);
}

// A damaged log cannot fill the memory with its bad records: the first ones are kept with their
// text, the rest counted.
TEST(LogSource, BadRecordsBeyondTheKeptOnesAreCountedOnly) {
  std::string text = "(1.000) can0 100#01\n";
  for (std::size_t i = 0; i < LogSource::kKeptBadRecords + 500; ++i) text += "garbage\n";
  text += "(2.000) can0 100#02\n";
  std::istringstream in(text);
  const std::unique_ptr<LogSource> source = candump_log_format().open(in);
  std::size_t n = 0, reported = 0;
  source->on_bad_record([&](const BadLine&) { ++reported; });
  while (source->next()) ++n;
  EXPECT_EQ(n, 2u);
  EXPECT_EQ(source->bad_records(), LogSource::kKeptBadRecords + 500);
  EXPECT_EQ(source->records().bad_lines.size(), LogSource::kKeptBadRecords);
  EXPECT_EQ(source->records().bad_lines.back().line, LogSource::kKeptBadRecords + 1);
}

// A read error in the middle of a log (a disk that fails after the first 256 KiB block): the frames
// of the blocks read are replayed, then one bad record says the log could not be read on; it is not
// taken for the log's end.
TEST(LogSource, AReadErrorEndsTheLogWithABadRecord) {
  struct Failing : std::streambuf {
    std::string text = [] {
      std::string t;
      for (int i = 0; i < 8192; ++i) t += "(1.0000000) can0 100#0102030405\n";  // 32 bytes: one block
      return t;
    }();
    bool served = false;
    int_type underflow() override {
      if (served) throw std::ios_base::failure("EIO");
      served = true;
      setg(text.data(), text.data(), text.data() + text.size());
      return traits_type::to_int_type(text[0]);
    }
  } buffer;
  std::istream in(&buffer);
  const std::unique_ptr<LogSource> source = candump_log_format().open(in);
  std::size_t n = 0;
  while (source->next()) ++n;
  EXPECT_EQ(n, 8192u);
  ASSERT_EQ(source->bad_records(), 1u);
  EXPECT_EQ(source->records().bad_lines[0].why, "read error: the log could not be read on from here");
}

// The writers' one loop: a chunk is written once it reaches its size (the rest at the end), and the
// progress is told the frames in the chunks written so far.
TEST(LogSource, WritersHandOutChunksOnceFullAndTheRestAtTheEnd) {
  ParsedLogSource frames(drive(7));
  std::vector<std::string> chunks;
  std::vector<std::size_t> told;
  const std::size_t n = write_log_chunks(
      frames, 10, [](const CanFrame& f, std::string& chunk) { chunk += "f" + std::to_string(f.data[0]) + "; "; },
      [&](const std::string& chunk) { chunks.push_back(chunk); }, [&](std::size_t w) { told.push_back(w); });
  EXPECT_EQ(n, 7u);
  EXPECT_EQ(chunks, (std::vector<std::string>{"f0; f1; f2; ", "f3; f4; f5; ", "f6; "}));
  EXPECT_EQ(told, (std::vector<std::size_t>{3, 6}));
  ParsedLogSource none{ParsedLog{}};
  EXPECT_EQ(write_log_chunks(none, 10, [](const CanFrame&, std::string& c) { c += "x"; },
                             [&](const std::string&) { ADD_FAILURE() << "an empty log has no chunk"; }, [](std::size_t) {}),
            0u);
}
