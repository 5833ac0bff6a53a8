// meter-linkdump [--link ENDPOINT] [-o FILE] [--duration SEC] [--until-closed] [-q]
// Connects to the controller's link as a view does and prints every message it receives as one
// line (meter/protocol/recording.hpp, docs/protocol.md "Link recordings"); -o also records the
// lines to FILE, which meter-linkplay replays. Ends on SIGINT/SIGTERM, after --duration, or with
// --until-closed once a link that was up is closed or lost.
#include <chrono>
#include <fstream>
#include <iostream>
#include <string>
#include <variant>

#include <CLI/CLI.hpp>

#include "meter/protocol/link.hpp"
#include "meter/protocol/recording.hpp"
#include "tool_run.hpp"

int main(int argc, char** argv) {
  using namespace meter::protocol;
  CLI::App app{"meter-linkdump: print every message of the controller-to-view link as one line, and record it"};
  std::string link = "default", output;
  double duration_s = 0.0;
  bool until_closed = false, quiet = false;
  int link_timeout_ms = 1000;
  app.add_option("--link", link, "controller endpoint unix:/path | tcp:host:port | default")->capture_default_str();
  app.add_option("-o,--output,--record", output, "also write the lines to FILE (a recording meter-linkplay replays)");
  app.add_option("--duration", duration_s, "stop after SEC seconds (0 = until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--until-closed", until_closed, "stop once the link was up and is then closed or lost");
  app.add_flag("-q,--quiet", quiet, "do not print the lines (record only)");
  std::string key_file;
  bool insecure_link = false;
  app.add_option("--key-file", key_file, kKeyFileHelp);
  app.add_flag("--insecure-link", insecure_link, kInsecureLinkHelp);
  app.add_option("--link-timeout", link_timeout_ms, "milliseconds of silence after which the link counts as lost")
      ->check(CLI::Range(30, 60000))->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    std::ofstream record;
    if (!output.empty()) {
      record.open(output);
      if (!record) {
        std::cerr << "meter-linkdump: cannot write " << output << "\n";
        return 1;
      }
      record << recording_header(catalog_hash()) << "\n" << std::flush;
    }
    auto options = link_options("meter-linkdump", std::chrono::milliseconds(link_timeout_ms));
    // A dump started before the controller should join within a few heartbeats, not after 2 s of backoff.
    options.reconnect_max = std::chrono::milliseconds(200);
    options.key_file = key_file;
    options.insecure_link = insecure_link;
    Subscriber sub(endpoint_from_option(link), options);
    std::uint64_t messages = 0;
    sub.set_frame_observer([&](const Frame& frame) {
      const std::string line = format_line(RecordedFrame{tool::monotonic_ns(), frame});
      ++messages;
      if (!quiet) std::cout << line << "\n" << std::flush;
      if (record.is_open()) record << line << "\n" << std::flush;
    });
    tool::stop_on_signals();
    const auto start = std::chrono::steady_clock::now();
    const auto duration = std::chrono::duration<double>(duration_s);
    bool was_up = false;
    while (!tool::g_stop) {
      sub.poll(std::chrono::milliseconds(50));
      if (sub.link_up()) was_up = true;
      if (until_closed && was_up && !sub.link_up()) break;
      if (duration_s > 0 && std::chrono::steady_clock::now() - start >= duration) break;
    }
    if (record.is_open() && !record) {
      std::cerr << "meter-linkdump: write error on " << output << "\n";
      return 1;
    }
    std::cerr << "meter-linkdump: " << messages << " messages" << (output.empty() ? "" : " recorded to " + output)
              << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "meter-linkdump: " << e.what() << "\n";
    return 1;
  }
}
