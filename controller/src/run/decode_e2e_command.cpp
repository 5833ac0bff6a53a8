// decode --e2e: what is protected, each frame's check, and the summary per message.
#include "meter/controller/run/decode_e2e_command.hpp"

#include <cstdio>
#include <ostream>

#include "command_output.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/e2e_detect.hpp"
#include "meter/controller/e2e/e2e_guard.hpp"
#include "meter/controller/input/log_format.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"

namespace meter::controller {
namespace {

// The guard and, on err, where its configuration comes from.
E2eGuard configured_guard(const Database& db, const std::string& map_path, std::ostream& err) {
  const InputDbc inputs[] = {{"", &db}};
  E2eSettings settings;
  std::string file = map_path;
  if (!map_path.empty()) {
    Mapping map = load_mapping(map_path);
    settings = map.e2e;
    if (settings.messages.empty() && !settings.detect)
      err << "e2e: " << map_path << " configures no [e2e MESSAGE] section: using the DBC's conventions\n";
    else
      err << "e2e: checking what " << map_path << " configures (" << settings.messages.size() << " [e2e] message section(s)"
          << (settings.detect ? ", and the DBC's conventions" : "") << ")\n";
    settings.detect = settings.detect || settings.messages.empty();
  } else {
    settings.detect = true;
  }
  if (!settings.detect) return build_e2e_guard(inputs, settings, file.empty() ? db.file : file);
  const E2eDetection d = detect_e2e(db);  // once: reported here, then added to the guard
  if (d.make.empty())
    err << "e2e: " << db.file << ": the file name names no make known here: checksums are not checked, counters are\n";
  else
    err << "e2e: " << db.file << ": make " << d.make << " (from the file name): checksum algorithm " << to_string(d.checksum)
        << "\n";
  for (const std::string& note : d.notes) err << "e2e:   " << note << "\n";
  if (d.messages.empty()) err << "e2e: " << db.file << ": no message has a checksum or counter signal: nothing to check\n";
  settings.detect = false;  // the configured sections first (the map file wins), then the detection
  E2eGuard guard = build_e2e_guard(inputs, settings, file.empty() ? db.file : file);
  add_detected_e2e(guard, db, 0, d);
  return guard;
}

void write_row(std::string& row, const CanFrame& f, const DbcMessage& m, const FrameCheck& r) {
  char ts[32];
  std::snprintf(ts, sizeof ts, "%lld.%06lld", static_cast<long long>(f.timestamp_ns / 1000000000LL),
                static_cast<long long>((f.timestamp_ns % 1000000000LL) / 1000));
  row.clear();
  row += ts;
  row += ',' + m.name + ',' + std::string(to_string(r.checksum)) + ',';
  if (r.checksum == ChecksumStatus::Ok || r.checksum == ChecksumStatus::Bad) row += std::to_string(r.received) + ',' + std::to_string(r.expected);
  else row += ',';
  row += ',';
  if (r.has_counter && r.checksum != ChecksumStatus::ShortFrame) row += std::to_string(r.counter);
  row += ',';
  if (r.has_counter && (r.checksum == ChecksumStatus::Ok || r.checksum == ChecksumStatus::NotChecked))
    row += to_string(r.counter_result.status);
  row += r.usable ? ",yes\n" : ",no\n";
}

bool summarise(const E2eGuard& guard, std::ostream& err) {
  std::uint64_t checked = 0, refused = 0, lost = 0;
  for (const auto& e : guard.entries()) checked += e.stats.checked, refused += e.stats.refused(), lost += e.stats.lost;
  err << "e2e summary: " << checked << " frames checked, " << refused << " refused, " << lost
      << " frames lost (tolerated counter skips), " << guard.entries().size() << " protected message(s)\n";
  bool mismatch = false;
  std::string unseen;
  for (const auto& e : guard.entries()) {
    const E2eMessage& m = e.message;
    const E2eMessageStats& s = e.stats;
    if (s.checked == 0) {
      unseen += (unseen.empty() ? "" : ", ") + m.message->name;
      continue;
    }
    err << "e2e:   " << m.message->name << " (" << hex(m.message->id) << ", " << to_string(m.spec.checksum) << "): " << s.checked
        << " checked, " << s.refused() << " refused (" << s.checksum_failed << " checksum, " << s.short_frames << " short, "
        << s.repeated << " repeated, " << s.wrong_sequence << " wrong sequence, " << s.syncing << " resynchronising), "
        << s.skips << " counter skips (" << s.lost << " frames lost)\n";
  }
  if (!unseen.empty()) err << "e2e:   not in the log: " << unseen << "\n";
  for (const auto& e : guard.entries()) {
    if (!guard.likely_mismatch(e)) continue;
    mismatch = true;
    const E2eMessageStats& s = e.stats;
    err << "e2e: likely configuration mismatch: " << e.message.message->name << " (" << hex(e.message.message->id) << ") refused "
        << s.refused() << " of " << s.checked << " frames ("
        << (s.checksum_failed >= s.refused() / 2 ? "checksum " + std::string(to_string(e.message.spec.checksum)) +
                                                      " does not fit: another make's algorithm, data id or DBC?"
                                                : "counter out of step: another counter signal or tolerance?")
        << "; configured by " << (e.message.spec.origin.empty() ? "the map file" : e.message.spec.origin) << ")\n";
  }
  return mismatch;
}

}  // namespace

int decode_e2e_command(const std::string& dbc_path, const std::string& log_path, const std::string& map_path,
                       std::ostream& out, std::ostream& err, bool strict) {
  try {
    Database db = load_dbc(dbc_path, DbcOptions{strict});
    report_dbc_warnings(db, err);
    E2eGuard guard = configured_guard(db, map_path, err);
    const std::unique_ptr<LogSource> log = open_log_source(log_path);  // streamed, a frame at a time
    report_bad_lines(*log, log_path, err);
    out << "timestamp,message,checksum,received,expected,counter,counter_status,used\n";
    std::string row;
    while (const CanFrame* frame = log->next()) {
      const CanFrame& f = *frame;
      if (f.error || f.rtr) continue;
      const DbcMessage* m = db.find(f.id, f.extended);
      const int i = m ? guard.find(m) : -1;
      if (i < 0) continue;
      const FrameCheck r = guard.check(static_cast<std::size_t>(i), f.id, std::span<const std::uint8_t>(f.data.data(), f.len));
      write_row(row, f, *m, r);
      out << row;
    }
    report_bad_line_count(*log, log_path, err);
    return summarise(guard, err) ? 2 : 0;
  } catch (const std::exception& e) {
    err << "meter-controller decode --e2e: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
