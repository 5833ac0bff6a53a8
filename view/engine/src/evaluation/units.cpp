// Unit systems of the readouts and printed scales: km/h <-> mph, km <-> mi, °C <-> °F.
//
// Conversions are exact definitions (1 mi = 1.609344 km, °F = °C x 9/5 + 32). The speed and
// distance conversions are linear through zero, so the UN R39 band the controller applies in
// km/h (0 <= shown - true <= 0.1 true + 4 km/h) arrives in mph exactly as
// 0 <= shown - true <= 0.1 true + 4/1.609344 mph (= 2.4855 mph): the ratio part keeps its 10 %,
// the offset is converted, and a value inside the km/h band is inside the mph band.
#include "meter/engine/evaluation/scene_features.hpp"

namespace meter::engine {

namespace {
constexpr double kKmPerMile = 1.609344;
}

bool shows_imperial(const UnitSystem& units, Quantity q) {
  switch (q) {
    case Quantity::None: return false;
    case Quantity::Speed:
    case Quantity::Distance: return units.imperial_distance;
    case Quantity::Temperature: return units.fahrenheit;
  }
  return false;
}

double to_imperial(Quantity q, double metric) {
  switch (q) {
    case Quantity::None: return metric;
    case Quantity::Speed:
    case Quantity::Distance: return metric / kKmPerMile;
    case Quantity::Temperature: return metric * 9.0 / 5.0 + 32.0;
  }
  return metric;
}

double to_metric(Quantity q, double imperial) {
  switch (q) {
    case Quantity::None: return imperial;
    case Quantity::Speed:
    case Quantity::Distance: return imperial * kKmPerMile;
    case Quantity::Temperature: return (imperial - 32.0) * 5.0 / 9.0;
  }
  return imperial;
}

Binding imperial_binding(const Binding& metric) {
  Binding b = metric;
  const Quantity q = metric.units.quantity;
  const ImperialLook& look = metric.units.imperial;
  b.input = look.input ? *look.input : std::array<double, 2>{to_imperial(q, metric.input[0]), to_imperial(q, metric.input[1])};
  if (look.format) b.format = *look.format;
  if (look.failsafe_text) b.failsafe_text = *look.failsafe_text;
  if (metric.failsafe_value) b.failsafe_value = to_imperial(q, *metric.failsafe_value);
  // A threshold is a value of the quantity too (a lamp lit above a speed).
  if (metric.kind != BindingKind::Animation && metric.kind != BindingKind::Morph) b.threshold = to_imperial(q, metric.threshold);
  return b;
}

}  // namespace meter::engine
