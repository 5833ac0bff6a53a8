// convert-log: load a log through the log formats, write it through a format's writer.
#include "meter/controller/run/convert_log_command.hpp"

#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>

#include "command_output.hpp"
#include "meter/controller/input/log_channel.hpp"
#include "meter/controller/input/log_format.hpp"

namespace meter::controller {
namespace {

const LogFormat& convert_output_format(const ConvertLogOptions& o) {
  std::string writable;
  for (const LogFormat& f : log_formats()) {
    if (!f.write) continue;
    writable += (writable.empty() ? "" : ", ") + std::string(f.name) + " (" + std::string(f.extensions.front()) + ")";
    if (f.name == o.format) return f;
  }
  if (o.format.empty())
    if (const LogFormat* f = find_log_writer(o.out)) return *f;
  throw std::invalid_argument(o.format.empty() ? o.out + ": the output format is not told by its extension; name one with --format: " + writable
                                               : "--format " + o.format + ": expected one of " + writable);
}

}  // namespace

int convert_log_command(const ConvertLogOptions& o, std::ostream& out_text, std::ostream& err) {
  try {
    const LogFormat& format = convert_output_format(o);
    const LogAddress in = parse_log_address(o.in);
    std::error_code ec;
    if (std::filesystem::equivalent(in.path, o.out, ec)) throw std::invalid_argument(o.out + ": is the input itself; write to another file");
    // Streamed: each frame is written as it is read, so a log of any length converts in the same memory.
    const std::unique_ptr<LogSource> log = open_log_source(in.path, in.channel);
    report_bad_lines(*log, in.path, err);
    std::ofstream file(o.out, std::ios::binary | std::ios::trunc);
    if (!file) throw std::runtime_error(o.out + ": cannot open for writing");
    const std::size_t total = format.write(*log, file, [&](std::size_t written) {
      if (o.progress) err << "\rconvert-log: " << written << " frames written" << std::flush;
    });
    file.close();
    if (o.progress) err << "\rconvert-log: " << total << " frames written\n";
    if (!file) throw std::runtime_error(o.out + ": write error");
    report_bad_line_count(*log, in.path, err);
    out_text << o.in << ": " << total << " frames (" << log->records().format << ", " << log->bad_records() << " bad records, "
             << log->records().skipped << " records of other kinds skipped) -> " << o.out << " (" << format.name << ")\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-controller convert-log: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
