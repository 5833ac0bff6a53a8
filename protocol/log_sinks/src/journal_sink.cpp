// The systemd journal: each record as its own fields through the journal's native protocol
// (sd_journal_sendv), so `journalctl -u meter-view -o json` shows METER_COMPONENT, METER_SIGNAL ...
#include <sys/uio.h>
#include <unistd.h>

// The record's own CODE_FILE / CODE_LINE (where it was written), not this sink's.
#define SD_JOURNAL_SUPPRESS_LOCATION
#include <systemd/sd-journal.h>

#include <iostream>

#include "meter/log_sinks/open_log_sink.hpp"
#include "meter/protocol/log/log_format.hpp"

namespace meter::log_sinks {

namespace {

constexpr const char* kJournalSocket = "/run/systemd/journal/socket";  // journald's native protocol

class JournalSink : public protocol::RecordSink {
 public:
  explicit JournalSink(std::string program) : program_(std::move(program)) {}
  void write(const protocol::LogRecord& r) override {
    const std::vector<std::string> fields = protocol::journal_fields(r, program_);
    std::vector<iovec> iov;
    iov.reserve(fields.size());
    for (const std::string& f : fields) iov.push_back(iovec{const_cast<char*>(f.data()), f.size()});
    // A record the journal refused (too large, out of memory) still reaches stderr, as plain text.
    if (sd_journal_sendv(iov.data(), static_cast<int>(iov.size())) < 0) std::cerr << protocol::format_text(r) << '\n';
  }

 private:
  std::string program_;
};

}  // namespace

std::unique_ptr<protocol::RecordSink> make_journal_sink(std::string program) {
  // sd_journal_sendv drops records silently when no journal listens; without its socket the
  // records go to stderr as plain text instead, and the first one says why.
  if (::access(kJournalSocket, F_OK) != 0) {
    auto text = protocol::make_stream_sink(std::cerr, protocol::LogForm::Text, program);
    protocol::LogRecord r;
    r.level = protocol::LogLevel::Warning;
    r.component = "log";
    r.prefix = program + ": ";
    r.message = std::string("--log journal: no journal listens at ") + kJournalSocket + "; plain text on stderr instead";
    text->write(r);
    return text;
  }
  return std::make_unique<JournalSink>(std::move(program));
}

}  // namespace meter::log_sinks
