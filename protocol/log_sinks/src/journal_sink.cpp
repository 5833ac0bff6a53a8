// The systemd journal: each record as its own fields through the journal's native protocol
// (sd_journal_sendv), so `journalctl -u meter-view -o json` shows METER_COMPONENT, METER_SIGNAL ...
#include <sys/uio.h>
#include <systemd/sd-journal.h>

#include <iostream>

#include "meter/log_sinks/open_log_sink.hpp"
#include "meter/protocol/log/log_format.hpp"

namespace meter::log_sinks {

namespace {

class JournalSink : public protocol::RecordSink {
 public:
  explicit JournalSink(std::string program) : program_(std::move(program)) {}
  void write(const protocol::LogRecord& r) override {
    const std::vector<std::string> fields = protocol::journal_fields(r, program_);
    std::vector<iovec> iov;
    iov.reserve(fields.size());
    for (const std::string& f : fields) iov.push_back(iovec{const_cast<char*>(f.data()), f.size()});
    // No journal (not under systemd): the record still reaches stderr, as plain text.
    if (sd_journal_sendv(iov.data(), static_cast<int>(iov.size())) < 0) std::cerr << protocol::format_text(r) << '\n';
  }

 private:
  std::string program_;
};

}  // namespace

std::unique_ptr<protocol::RecordSink> make_journal_sink(std::string program) {
  return std::make_unique<JournalSink>(std::move(program));
}

}  // namespace meter::log_sinks
