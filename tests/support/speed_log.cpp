#include "speed_log.hpp"

#include "candump_line.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/can_frame.hpp"

namespace meter::testing {

void write_demo_speed_log(const std::filesystem::path& file, const std::function<double(double)>& speed_at,
                          double seconds) {
  const auto db = controller::load_dbc(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.dbc");
  const auto* msg = db.find("ESP_WheelSpeeds");
  if (msg == nullptr) throw std::runtime_error("demo.dbc lost ESP_WheelSpeeds");
  std::ofstream out(file);
  const std::int64_t t0_ns = 1'700'000'000'000'000'000LL;
  for (int i = 0; i * 0.02 <= seconds + 1e-9; ++i) {
    const double v = speed_at(i * 0.02);
    const std::pair<std::string_view, double> values[] = {{"VehicleSpeed", v}, {"WheelSpeedFL", v}, {"WheelSpeedFR", v}};
    out << candump_line(*msg, values, t0_ns + static_cast<std::int64_t>(i) * 20'000'000LL) << "\n";
  }
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace meter::testing
