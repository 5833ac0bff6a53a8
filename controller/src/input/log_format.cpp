// The recorded log formats this build reads, and how a file is matched to one.
#include "meter/controller/input/log_format.hpp"

#include <array>
#include <bitset>
#include <fstream>
#include <stdexcept>

#include "meter/controller/input/asc_log.hpp"
#include "meter/controller/input/blf_log.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/trc_log.hpp"

namespace meter::controller {

std::span<const LogFormat> log_formats() {
  // The registration: one entry per format, asked in this order.
  static const std::array formats{
      candump_log_format(),
      asc_log_format(),
      blf_log_format(),
      trc_log_format(),
  };
  return formats;
}

namespace {

bool has_extension(std::string_view path, std::string_view ext) {
  return path.size() > ext.size() && path.substr(path.size() - ext.size()) == ext;
}

// "line 3 '...'" for the first non-blank line of head, or "it is empty".
std::string first_line(std::string_view head) {
  std::size_t number = 0, pos = 0;
  while (pos < head.size()) {
    const std::size_t nl = head.find('\n', pos);
    const std::string_view line = trim_line_end(head.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
    pos = nl == std::string_view::npos ? head.size() : nl + 1;
    ++number;
    if (line.empty()) continue;
    std::string shown(line.substr(0, 60));
    for (char& c : shown)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
    return "line " + std::to_string(number) + " '" + shown + (line.size() > 60 ? "...'" : "'");
  }
  return "it is empty";
}

// "FILE: no usable CAN frame ...: FILE:1: why; FILE:2: why; FILE:3: why; and N more"
std::string no_frame_message(const std::string& path, const LogFormat& format, const ParsedLog& log) {
  std::string m = path + ": no usable CAN frame in this " + std::string(format.name) + " log";
  if (log.bad_lines.empty()) {
    m += log.skipped ? ": its " + std::to_string(log.skipped) + " record(s) hold no CAN frame" : ": it holds no record";
    return m;
  }
  constexpr std::size_t kShown = 3;
  for (std::size_t i = 0; i < log.bad_lines.size() && i < kShown; ++i)
    m += (i == 0 ? ": " : "; ") + path + ":" + std::to_string(log.bad_lines[i].line) + ": " + log.bad_lines[i].why;
  if (log.bad_lines.size() > kShown) m += "; and " + std::to_string(log.bad_lines.size() - kShown) + " more bad record(s)";
  return m;
}

std::string no_format_message(const std::string& path, std::string_view head) {
  std::string known;
  for (const LogFormat& f : log_formats()) {
    known += (known.empty() ? "" : "; ") + std::string(f.name) + ", e.g. '" + std::string(f.example) + "'";
    for (std::string_view ext : f.extensions) known += ", or any file named *" + std::string(ext);
  }
  return path + ": not a CAN log this build reads: " + first_line(head) + " starts no known format (" + known + ")";
}

}  // namespace

const LogFormat* find_log_format(std::string_view path, std::string_view head) {
  for (const LogFormat& f : log_formats())
    if (f.sniff(head)) return &f;
  for (const LogFormat& f : log_formats())
    for (std::string_view ext : f.extensions)
      if (has_extension(path, ext)) return &f;
  return nullptr;
}

const LogFormat* find_log_writer(std::string_view path) {
  for (const LogFormat& f : log_formats())
    if (f.write)
      for (std::string_view ext : f.extensions)
        if (has_extension(path, ext)) return &f;
  return nullptr;
}

std::string_view trim_line_end(std::string_view line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  return line;
}

// "FILE#N: no frame on channel N (the log's channels: 1, 2)"
std::string no_channel_message(const std::string& path, int channel, const std::bitset<256>& present) {
  std::string channels;
  for (int c = 0; c < 256; ++c)
    if (present[static_cast<std::size_t>(c)]) channels += (channels.empty() ? "" : ", ") + (c == 0 ? std::string("none") : std::to_string(c));
  return path + "#" + std::to_string(channel) + ": no frame on channel " + std::to_string(channel) + " (the log's channels: " + channels + ")";
}

std::unique_ptr<LogSource> open_log_source(const std::string& path, int channel) {
  auto in = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*in) throw std::runtime_error(path + ": cannot open the log for reading");
  std::string head(kLogSniffBytes, '\0');
  in->read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in->gcount()));
  const LogFormat* format = find_log_format(path, head);
  if (!format) throw std::runtime_error(no_format_message(path, head));
  in->clear();
  if (!in->seekg(0)) throw std::runtime_error(path + ": cannot read the log from its start again after recognising it (a pipe?); give a file");
  std::unique_ptr<LogSource> source = format->open(*in);
  source->file_ = std::move(in);
  source->window().format = format->name;
  source->only_channel(channel);
  const bool any = source->peek() != nullptr;
  if (source->file_->bad()) throw std::runtime_error(path + ": read error in the log");
  if (!any && channel != 0 && source->channels_seen().any()) throw std::runtime_error(no_channel_message(path, channel, source->channels_seen()));
  if (!any) throw std::runtime_error(no_frame_message(path, *format, source->records()));
  return source;
}

std::string log_format_names() {
  std::string names;
  for (const LogFormat& f : log_formats()) names += (names.empty() ? "" : ", ") + std::string(f.name);
  return names;
}

}  // namespace meter::controller
