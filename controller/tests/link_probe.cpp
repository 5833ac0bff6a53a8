// link_probe ENDPOINT SECONDS: a protocol subscriber for the vcan tests, so they judge what went
// over the link rather than what the controller says it published. After SECONDS it prints, for
// every catalog signal that was ever valid, "NAME valid_max=V last_valid=V valid_samples=N".
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/link.hpp"

int main(int argc, char** argv) {
  using namespace meter::protocol;
  if (argc != 3) {
    std::fprintf(stderr, "usage: link_probe ENDPOINT SECONDS\n");
    return 2;
  }
  LinkOptions options;
  options.insecure_link = true;  // the VM tests' lab link (their controller runs --insecure-link)
  Subscriber sub(Endpoint::parse(argv[1]), options);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[2]));
  struct Seen {
    long samples = 0;
    double max = 0, last = 0;
  };
  const auto signals = catalog();
  std::vector<Seen> seen(signals.size());
  bool ever_up = false;
  while (std::chrono::steady_clock::now() < until) {
    sub.poll(std::chrono::milliseconds(20));
    if (!sub.link_up()) continue;
    ever_up = true;
    for (std::size_t i = 0; i < signals.size(); ++i) {
      const SignalState& s = sub.get(signals[i].id);
      if (s.status != SignalStatus::Valid) continue;
      Seen& x = seen[i];
      x.max = x.samples == 0 ? s.value : std::max(x.max, s.value);
      x.last = s.value;
      ++x.samples;
    }
  }
  std::printf("link %s\n", ever_up ? "up" : "never up");
  for (std::size_t i = 0; i < signals.size(); ++i)
    if (seen[i].samples > 0)
      std::printf("%s valid_max=%.9g last_valid=%.9g valid_samples=%ld\n", std::string(signals[i].name).c_str(), seen[i].max,
                  seen[i].last, seen[i].samples);
  return ever_up ? 0 : 1;
}
