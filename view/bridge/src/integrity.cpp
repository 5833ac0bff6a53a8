#include "meter/bridge/integrity.hpp"

namespace meter::bridge {

const char* to_string(SafetyKind kind) {
  switch (kind) {
    case SafetyKind::Telltale: return "telltale";
    case SafetyKind::Needle: return "needle";
    case SafetyKind::Readout: return "readout";
  }
  return "?";
}

}  // namespace meter::bridge
