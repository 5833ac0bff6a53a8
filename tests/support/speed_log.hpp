// A candump -L log of the demo vehicle's speed message (ESP_WheelSpeeds in
// controller/vehicles/demo/demo.dbc) every 20 ms, for tests that drive meter-controller from a log.
#pragma once

#include <filesystem>
#include <functional>

namespace meter::testing {

// Frames at t = 0, 0.02, ... <= seconds carrying speed_at(t) km/h in VehicleSpeed and both front
// wheel speeds. Throws std::runtime_error if the demo DBC lost the message.
void write_demo_speed_log(const std::filesystem::path& file, const std::function<double(double)>& speed_at,
                          double seconds);

}  // namespace meter::testing
