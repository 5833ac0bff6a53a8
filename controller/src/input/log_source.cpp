// The window of parsed frames a log source holds, refilled from its reader as it empties.
#include "meter/controller/input/log_source.hpp"

#include <algorithm>

namespace meter::controller {

void LogSource::refill() {
  window_.frames.clear();
  pos_ = 0;
  const std::size_t bad_before = window_.bad_lines.size();
  if (!read_more()) {
    ended_ = true;
    if (watched_ && watched_->bad()) window_.bad_lines.push_back({window_.lines, "read error: the log could not be read on from here"});
  }
  if (window_.bad_lines.size() > kKeptBadRecords && window_.bad_lines.size() > bad_before) {
    const std::size_t keep = std::max(bad_before, kKeptBadRecords);
    bad_dropped_ += window_.bad_lines.size() - keep;
    window_.bad_lines.resize(keep);
  }
  if (report_)
    for (std::size_t i = bad_before; i < window_.bad_lines.size(); ++i) report_(window_.bad_lines[i]);
  peak_ = std::max(peak_, window_.frames.size());
  for (const CanFrame& f : window_.frames) seen_.set(f.channel);
}

const CanFrame* LogSource::peek() {
  for (;;) {
    while (pos_ < window_.frames.size()) {
      const CanFrame& f = window_.frames[pos_];
      if (channel_ == 0 || f.channel == channel_) return &f;
      ++pos_;
    }
    if (ended_) return nullptr;
    refill();
  }
}

const CanFrame* LogSource::next() {
  const CanFrame* f = peek();
  if (f) ++pos_;
  return f;
}

ParsedLogSource::ParsedLogSource(ParsedLog log) : frames_(std::move(log.frames)) {
  log.frames.clear();
  window() = std::move(log);
}

bool ParsedLogSource::read_more() {
  if (next_ < frames_.size()) window().frames.push_back(frames_[next_++]);
  return next_ < frames_.size();
}

ParsedLog read_whole_log(LogSource& source) {
  std::vector<CanFrame> frames;
  while (const CanFrame* f = source.next()) frames.push_back(*f);
  ParsedLog log = source.records();
  log.frames = std::move(frames);
  return log;
}

}  // namespace meter::controller
