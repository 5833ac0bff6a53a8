// meter-drivecycle: writes the demo vehicle's deterministic drive-cycle log (candump -L).
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "drivecycle.hpp"

int main(int argc, char** argv) {
  CLI::App app{"meter-drivecycle: generate the demo drive cycle (ignition on, idle, acceleration through the "
               "gears to 130 km/h, cruise, indicators, braking to a stop, an oil-pressure warning) as a "
               "candump -L log, encoded with the demo DBC. The output is byte-identical on every run."};
  std::string dbc, out;
  double duration = meter::drivecycle::kDurationS;
  std::string iface = "vcan0";
  app.add_option("--dbc", dbc, "The demo vehicle DBC (controller/vehicles/demo/demo.dbc)")->required()->check(CLI::ExistingFile);
  app.add_option("-o,--out", out, "Output log file ('-' = stdout)")->required();
  app.add_option("--duration", duration, "Seconds of drive cycle to write")->check(CLI::Range(1.0, 3600.0));
  app.add_option("--interface", iface, "Interface name written in the log");
  CLI11_PARSE(app, argc, argv);
  try {
    auto db = meter::controller::load_dbc(dbc);
    std::string log = meter::drivecycle::generate_log(db, duration, iface);
    if (out == "-") {
      std::cout << log;
    } else {
      std::ofstream f(out, std::ios::binary);
      if (!(f << log)) throw std::runtime_error(out + ": cannot write");
    }
  } catch (const std::exception& e) {
    std::cerr << "meter-drivecycle: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
