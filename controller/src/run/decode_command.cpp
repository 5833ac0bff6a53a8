// decode: a recorded CAN log (any format of log_format.hpp) through the DBC to CSV, one row per decoded signal.
#include <cstdio>
#include <ostream>
#include <set>

#include "command_output.hpp"
#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/log_format.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/controller/run/decode_command.hpp"

namespace meter::controller {

int decode_command(const std::string& dbc_path, const std::string& log_path, const std::string& map_path,
                   std::ostream& out, std::ostream& err, bool strict) {
  try {
    Database db = load_dbc(dbc_path, DbcOptions{strict});
    report_dbc_warnings(db, err);
    std::set<std::pair<const DbcMessage*, int>> wanted;
    if (!map_path.empty()) {
      Mapping map = load_mapping(map_path);
      Model check(&db, map);  // validates every source against the DBC
      for (const auto& o : map.outputs)
        for (const auto& s : o.sources) {
          if (is_modbus_source(s)) continue;
          const DbcSource src = resolve_dbc_source(&db, s, map.file, o.line);
          wanted.emplace(src.message, src.signal);
        }
    }
    const std::unique_ptr<LogSource> log = open_log_source(log_path);  // streamed, a frame at a time
    report_bad_lines(*log, log_path, err);
    out << "timestamp,message,signal,raw,physical,unit,status\n";
    std::vector<DecodedSignal> decoded;
    std::uint64_t unknown = 0;
    std::string row;
    while (const CanFrame* frame = log->next()) {
      const CanFrame& f = *frame;
      if (f.error || f.rtr) continue;
      const DbcMessage* m = db.find(f.id, f.extended);
      if (!m) {
        ++unknown;
        continue;
      }
      decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), decoded);
      char ts[32];
      std::snprintf(ts, sizeof ts, "%lld.%06lld", static_cast<long long>(f.timestamp_ns / 1000000000LL),
                    static_cast<long long>((f.timestamp_ns % 1000000000LL) / 1000));
      for (const auto& d : decoded) {
        if (!wanted.empty() && !wanted.count({m, d.signal})) continue;
        const DbcSignal& s = signal_of(*m, d);
        row.clear();
        row += ts;
        row += ',';
        row += m->name;
        row += ',';
        row += s.name;
        row += ',';
        if (s.value_type == ValueType::Integer && s.is_signed) row += std::to_string(d.raw_signed());
        else row += std::to_string(d.raw);
        row += ',';
        row += d.status == DecodeStatus::NotFinite ? std::string() : fmt_double(d.physical);
        row += ',';
        row += csv_field(s.unit);
        row += ',';
        row += to_string(d.status);
        row += '\n';
        out << row;
      }
    }
    report_bad_line_count(*log, log_path, err);
    if (unknown) err << log_path << ": " << unknown << " frame(s) with ids the DBC does not define\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-controller decode: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
