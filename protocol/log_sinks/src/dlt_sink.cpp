// COVESA DLT through libdlt: the program registers its application id (MCTL, MVEW, MTOL) and one
// context per component (docs/logging.md); each record is a verbose message: the text, then one
// "key=value" string per field. Without a dlt-daemon libdlt keeps the messages in its ring buffer
// (dropping the oldest when full) and a thread of its own retries the daemon's FIFO; nothing here
// waits for it, and at exit it waits at most kExitResendMs.
#include <dlt/dlt.h>

#include <map>

#include "meter/log_sinks/open_log_sink.hpp"
#include "meter/protocol/log/log_format.hpp"

namespace meter::log_sinks {

namespace {

DltLogLevelType dlt_level(protocol::LogLevel level) {
  switch (level) {
    case protocol::LogLevel::Error: return DLT_LOG_ERROR;
    case protocol::LogLevel::Warning: return DLT_LOG_WARN;
    case protocol::LogLevel::Info: return DLT_LOG_INFO;
    case protocol::LogLevel::Debug: return DLT_LOG_DEBUG;
  }
  return DLT_LOG_INFO;
}

constexpr std::uint32_t kExitResendMs = 200;

class DltSink : public protocol::RecordSink {
 public:
  DltSink(const std::string& program, protocol::LogLevel threshold) : threshold_(dlt_level(threshold)) {
    dlt_log_init(DLT_LOG_TO_STDERR);  // libdlt's own notes (no daemon yet ...) on stderr, never stdout
    dlt_register_app(protocol::dlt_app_id(program).c_str(), program.c_str());
    // At exit libdlt waits for a daemon to take what it still buffers: at most this long, so a
    // process without a daemon still ends at once.
    dlt_set_resend_timeout_atexit(kExitResendMs);
  }
  ~DltSink() override {
    for (auto& [id, ctx] : contexts_) dlt_unregister_context(&ctx);
    dlt_unregister_app();
  }
  DltSink(const DltSink&) = delete;
  DltSink& operator=(const DltSink&) = delete;

  void write(const protocol::LogRecord& r) override {
    DltContextData data;
    if (dlt_user_log_write_start(&context(r.component), &data, dlt_level(r.level)) <= 0) return;
    dlt_user_log_write_string(&data, r.message.c_str());
    for (const protocol::LogField& f : r.fields) dlt_user_log_write_string(&data, (f.key + "=" + f.value).c_str());
    dlt_user_log_write_finish(&data);
  }

 private:
  DltContext& context(const std::string& component) {
    const std::string id = protocol::dlt_context_id(component);
    auto it = contexts_.find(id);
    if (it == contexts_.end()) {
      it = contexts_.emplace(id, DltContext{}).first;
      // The context's initial level is --log-level's; the daemon may change it at run time.
      dlt_register_context_ll_ts(&it->second, id.c_str(), component.c_str(), threshold_, DLT_TRACE_STATUS_DEFAULT);
    }
    return it->second;
  }

  DltLogLevelType threshold_;
  std::map<std::string, DltContext> contexts_;
};

}  // namespace

std::unique_ptr<protocol::RecordSink> make_dlt_sink(std::string program, protocol::LogLevel threshold) {
  return std::make_unique<DltSink>(program, threshold);
}

}  // namespace meter::log_sinks
