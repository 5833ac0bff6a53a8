// A recorded log read a frame at a time: the replay, the merge of several logs, decode and
// convert-log pull the next frame when they need it, and the reader parses on only then (a line,
// a BLF object). Only a window of parsed frames is held, never the whole log, so a log of any
// length replays in the same memory. Frames come in file order: a log whose times step back is
// replayed in that order (the frame that steps back is handed over at once, being already due).
#pragma once

#include <bitset>
#include <cstddef>
#include <functional>
#include <istream>
#include <memory>
#include <string>
#include <vector>

#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

class LogSource {
 public:
  virtual ~LogSource() = default;
  // The next frame in file order (of the channel asked, if one was), still held by the source: it
  // stays valid until the next call to next() or peek(); nullptr once the log has no more frames.
  const CanFrame* next();
  // The same frame next() would return, without taking it.
  const CanFrame* peek();
  // What has been read so far: the records read, those skipped, the bad ones with their numbers and
  // what was expected (frames: the window not handed over yet). After the end: the whole log's.
  const ParsedLog& records() const { return window_; }
  virtual std::size_t bad_records() const { return window_.bad_lines.size() + bad_dropped_; }
  // Only the frames of this channel (1..255) from now on; 0: every channel.
  void only_channel(int channel) { channel_ = channel; }
  // The channels of the frames read so far (0: frames without one).
  const std::bitset<256>& channels_seen() const { return seen_; }
  // The most frames the window ever held at once: the memory a replay holds for frames, whatever
  // the log's length (a text log: one line's; a BLF: one object's).
  std::size_t window_peak() const { return peak_; }
  // Called with each bad record from now on as the reading meets it (a log is reported as it
  // replays: its bad records are not all known before its first frame is).
  void on_bad_record(std::function<void(const BadLine&)> report) { report_ = std::move(report); }
  // The bad records kept with their text (more are counted only, so a damaged log cannot fill the memory).
  static constexpr std::size_t kKeptBadRecords = 1000;

 protected:
  // The reader's window: it appends the frames, bad records and counts of what it reads.
  ParsedLog& window() { return window_; }
  // Reads on (one record, or as few as it can) into window(); false once the log has no more
  // (the frames it appended on that last call are still handed over).
  virtual bool read_more() = 0;
  // The stream the reader reads: when it fails (a read error, not its end), the reading ends with
  // a bad record saying so, the frames before it kept.
  void watch(std::istream& in) { watched_ = &in; }
  // The file the source reads, when it owns it (opened by open_log_source()).
  std::unique_ptr<std::istream> file_;
  friend std::unique_ptr<LogSource> open_log_source(const std::string& path, int channel);

 private:
  ParsedLog window_;
  std::size_t pos_ = 0;  // the next frame of the window to hand over
  std::size_t peak_ = 0, bad_dropped_ = 0;
  std::bitset<256> seen_;
  int channel_ = 0;
  bool ended_ = false;
  std::function<void(const BadLine&)> report_;
  const std::istream* watched_ = nullptr;
  void refill();
};

// Frames already in memory (a log parsed whole, a test's frames) as a source.
class ParsedLogSource : public LogSource {
 public:
  explicit ParsedLogSource(ParsedLog log);

 private:
  std::vector<CanFrame> frames_;
  std::size_t next_ = 0;
  bool read_more() override;
};

// Every frame and record of a source, read to its end: a whole log in memory (tests, fuzzers,
// the benches; never run, decode or convert-log).
ParsedLog read_whole_log(LogSource& source);

}  // namespace meter::controller
