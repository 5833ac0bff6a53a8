// meter-linkplay RECORDING [--link ENDPOINT] [--speed realtime|max] [--wait-for-view SEC] [--linger SEC]
// Replays a meter-linkdump recording into a view: listens as the controller's end of the link,
// waits for a view, then sets every SNAPSHOT/DELTA update of the recording at its recorded time
// (realtime, relative to the first one) or as fast as the link takes them (max). The link's own
// messages (HELLO, HEARTBEAT, CLOSE) are this Publisher's, not replayed. --linger keeps serving the
// final state before closing.
#include <chrono>
#include <fstream>
#include <iostream>
#include <string>
#include <variant>

#include <CLI/CLI.hpp>

#include "meter/protocol/link.hpp"
#include "meter/protocol/recording.hpp"
#include "tool_run.hpp"

namespace {

using namespace meter::protocol;

// The Subscriber stores an entry without text as "no text": clear a text the signal had first.
void publish(Publisher& pub, const std::vector<SignalUpdate>& updates) {
  for (const auto& u : updates) {
    if (u.has_text || !pub.get(u.id).text.empty()) pub.set_text(u.id, u.has_text ? u.text : "", u.status);
    pub.set(u.id, u.value, u.status);
  }
}

const std::vector<SignalUpdate>* updates_of(const Frame& frame) {
  if (const auto* s = std::get_if<Snapshot>(&frame.message)) return &s->signals;
  if (const auto* d = std::get_if<Delta>(&frame.message)) return &d->signals;
  return nullptr;
}

// Polls the link until `until` (or a stop signal).
void serve_until(Publisher& pub, std::chrono::steady_clock::time_point until) {
  while (!tool::g_stop) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    if (left.count() <= 0) return;
    pub.poll(std::min(left, std::chrono::milliseconds(20)));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"meter-linkplay: replay a meter-linkdump recording into a view, as the controller's end of the link"};
  std::string recording, link = "default", speed = "realtime";
  double wait_s = 30.0, linger_s = 1.0;
  int link_timeout_ms = 1000;
  app.add_option("recording", recording, "recording written by meter-linkdump -o")->required()->check(CLI::ExistingFile);
  app.add_option("--link", link, "endpoint to listen on: unix:/path | tcp:host:port | default")->capture_default_str();
  app.add_option("--speed", speed, "realtime: the recorded timing; max: as fast as the link takes them")
      ->check(CLI::IsMember({"realtime", "max"}))->capture_default_str();
  app.add_option("--wait-for-view", wait_s, "seconds to wait for a view to connect before replaying")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--linger", linger_s, "seconds to keep serving the final state after the last message")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  std::string key_file;
  bool insecure_link = false;
  app.add_option("--key-file", key_file, kKeyFileHelp);
  app.add_flag("--insecure-link", insecure_link, kInsecureLinkHelp);
  app.add_option("--link-timeout", link_timeout_ms, "milliseconds of silence after which the link counts as lost")
      ->check(CLI::Range(30, 60000))->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    std::ifstream in(recording);
    if (!in) {
      std::cerr << "meter-linkplay: cannot read " << recording << "\n";
      return 1;
    }
    const auto frames = parse_recording(in, recording);
    auto options = link_options("meter-linkplay", std::chrono::milliseconds(link_timeout_ms));
    options.key_file = key_file;
    options.insecure_link = insecure_link;
    Publisher pub(endpoint_from_option(link), options);
    tool::stop_on_signals();
    using Clock = std::chrono::steady_clock;
    const auto wait_until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait_s));
    while (pub.peer_count() == 0 && !tool::g_stop && Clock::now() < wait_until) pub.poll(std::chrono::milliseconds(20));
    if (pub.peer_count() == 0) {
      std::cerr << "meter-linkplay: no view connected to " << pub.endpoint().to_string() << " within " << wait_s << " s\n";
      return 1;
    }
    const auto start = Clock::now();
    std::int64_t first_ns = 0;
    bool started = false;
    std::size_t replayed = 0, updates = 0;
    for (const auto& r : frames) {
      const auto* list = updates_of(r.frame);
      if (list == nullptr) continue;
      if (!started) first_ns = r.received_ns, started = true;
      if (speed == "realtime") serve_until(pub, start + std::chrono::nanoseconds(r.received_ns - first_ns));
      if (tool::g_stop) break;
      publish(pub, *list);
      pub.poll(std::chrono::milliseconds(0));
      ++replayed;
      updates += list->size();
    }
    serve_until(pub, Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(linger_s)));
    const std::chrono::duration<double> took = Clock::now() - start;
    std::cerr << "meter-linkplay: replayed " << replayed << " messages (" << updates << " signal updates) in "
              << took.count() << " s\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "meter-linkplay: " << e.what() << "\n";
    return 1;
  }
}
