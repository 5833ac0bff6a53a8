// Frames to Vector ASC text, a block of lines at a time.
#include "meter/controller/input/asc_log_writer.hpp"

#include <cstdio>
#include <string>

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_fields.hpp"
#include "meter/controller/input/write_log_chunks.hpp"

namespace meter::controller {
namespace {

// "Sun Sep 12 03:15:14.717 am 2021"
std::string asc_date_text(std::int64_t ns) {
  static const char* kDays[] = {"Sun", "Mon", "Tue", "Wed", "Thu", "Fri", "Sat"};
  static const char* kMonthNames[] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
  const std::int64_t seconds = ns >= 0 ? ns / 1000000000LL : (ns - 999999999LL) / 1000000000LL;
  const LocalTime t = local_time_of(seconds);
  const int hour12 = t.hour % 12 == 0 ? 12 : t.hour % 12;
  char text[64];
  std::snprintf(text, sizeof text, "%s %s %02d %02d:%02d:%02d.%03d %s %d", kDays[t.weekday], kMonthNames[t.month - 1], t.day,
                hour12, t.minute, t.second, static_cast<int>((ns - seconds * 1000000000LL) / 1000000), t.hour < 12 ? "am" : "pm",
                t.year);
  return text;
}

void asc_frame_line(const CanFrame& f, std::int64_t offset_ns, std::string& out) {
  char buf[96];
  const int channel = f.channel ? f.channel : 1;
  std::snprintf(buf, sizeof buf, "%11lld.%06lld ", static_cast<long long>(offset_ns / 1000000000LL),
                static_cast<long long>(offset_ns % 1000000000LL / 1000));
  out += buf;
  char id[16];
  std::snprintf(id, sizeof id, f.extended ? "%Xx" : "%X", f.id);
  if (f.error) {
    std::snprintf(buf, sizeof buf, "%d  ErrorFrame\n", channel);
    out += buf;
    return;
  }
  const bool fd = f.fd && !f.rtr;  // CAN FD knows no remote frame: one logged as such is written as a classic one
  if (fd) {
    std::snprintf(buf, sizeof buf, "CANFD %3d Rx %8s %d %d %x %2d", channel, id, (f.fd_flags & kCanFdBrs) ? 1 : 0,
                  (f.fd_flags & kCanFdEsi) ? 1 : 0, can_fd_len_to_dlc(f.len), f.len);
    out += buf;
  } else {
    std::snprintf(buf, sizeof buf, "%d  %-15s Rx   %c %X", channel, id, f.rtr ? 'r' : 'd', f.len8_dlc ? f.len8_dlc : f.len);
    out += buf;
  }
  static const char* kHex = "0123456789ABCDEF";
  for (std::size_t i = 0; i < (f.rtr ? 0 : f.len); ++i) {
    out += ' ';
    out += kHex[f.data[i] >> 4];
    out += kHex[f.data[i] & 15];
  }
  if (fd) {
    const unsigned flags = 0x1000u | ((f.fd_flags & kCanFdBrs) ? 0x2000u : 0) | ((f.fd_flags & kCanFdEsi) ? 0x4000u : 0);
    std::snprintf(buf, sizeof buf, " 0 0 %X 0 0 0 0 0", flags);
    out += buf;
  }
  out += '\n';
}

}  // namespace

std::size_t write_asc_log(LogSource& frames, std::ostream& out, const LogProgress& progress) {
  const CanFrame* head = frames.peek();
  const std::int64_t first = head ? head->timestamp_ns : 0;
  const std::int64_t start = first - ((first % 1000000) + 1000000) % 1000000;  // the first frame's millisecond
  const std::string header = "date " + asc_date_text(start) + "\nbase hex  timestamps absolute\ninternal events logged\n" +
                             "// version 9.0.0\nBegin Triggerblock " + asc_date_text(start) + "\n   0.000000 Start of measurement\n";
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  const std::size_t written = write_log_chunks(
      frames, kLogTextChunk,
      [start](const CanFrame& f, std::string& text) { asc_frame_line(f, f.timestamp_ns >= start ? f.timestamp_ns - start : 0, text); },
      write_to(out), progress);
  out << "End TriggerBlock\n";
  return written;
}

}  // namespace meter::controller
