// Display integrity at conversion: the kinds measured in order (telltales and readouts first,
// so the needles' annuli can avoid them) and the --report block.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "scene_shots.hpp"

namespace meter::convert {

IntegrityMeasurement measure_integrity(const Scene& scene, platform::GpuBackend& backend, const IntegrityOptions& options) {
  IntegrityMeasurement m;
  m.table.width = scene.config.size[0];
  m.table.height = scene.config.size[1];
  bool any = false;
  for (const auto& b : scene.config.bindings) any = any || b.kind != BindingKind::Morph;
  if (!any) return m;  // nothing safety-relevant: no renderer, no GL context needed
  SceneShots shots(scene, backend, options.msaa);
  measure_telltales(scene, shots, m);
  measure_readouts(scene, shots, m);
  SceneShots aliased(scene, backend, 1);
  measure_needles(scene, shots, aliased, options, m);
  // Lamps that are driver aids (a binding with "safety": false, e.g. a shift light) were measured
  // only so that no needle ring runs through them (a lit lamp in the needle's colour would be read
  // as needle); they are not monitored themselves.
  auto& regions = m.table.regions;
  regions.erase(std::remove_if(regions.begin(), regions.end(),
                               [&](const bridge::SafetyRegion& r) {
                                 if (r.kind != bridge::SafetyKind::Telltale || r.bindings.empty()) return false;
                                 for (int i : r.bindings)
                                   if (scene.config.bindings[std::size_t(i)].safety) return false;
                                 return true;
                               }),
                regions.end());
  return m;
}

std::string integrity_report(const IntegrityMeasurement& m) {
  std::ostringstream os;
  os << "integrity: " << m.table.regions.size() << " safety regions at " << m.table.width << "x" << m.table.height
     << "\n";
  char buf[256];
  for (const auto& r : m.table.regions) {
    std::snprintf(buf, sizeof buf, "  %-8s %-22s %-45s %4dx%-4d+%d+%d  ", to_string(r.kind), r.name.c_str(),
                  r.signal.c_str(), r.rect.width, r.rect.height, r.rect.x, r.rect.y);
    os << buf;
    switch (r.kind) {
      case bridge::SafetyKind::Telltale:
        for (const auto& l : r.telltale.looks) {
          std::snprintf(buf, sizeof buf, "%s %.0f,%.0f,%.0f; ", l.name.c_str(), l.mean[0], l.mean[1], l.mean[2]);
          os << buf;
        }
        std::snprintf(buf, sizeof buf, "tolerance %.1f", r.telltale.tolerance);
        break;
      case bridge::SafetyKind::Needle: {
        const auto& n = r.needle;
        std::snprintf(buf, sizeof buf, "pivot %.1f,%.1f annulus %.1f..%.1f px, %.1f..%.1f deg over %zu samples, tolerance %.2f deg",
                      n.pivot_x, n.pivot_y, n.r_min, n.r_max, n.samples.front().angle_deg, n.samples.back().angle_deg,
                      n.samples.size(), n.tolerance_deg);
        break;
      }
      case bridge::SafetyKind::Readout:
        std::snprintf(buf, sizeof buf, "anchor %d,%d size %d format \"%s\", tolerance %d px", r.readout.anchor_x,
                      r.readout.baseline_y, r.readout.size_px, r.readout.format.c_str(), r.readout.tolerance_pixels);
        break;
    }
    os << buf << "\n";
  }
  if (m.needle_interpolation_deg > 0) {
    std::snprintf(buf, sizeof buf, "  needle tables: largest interpolation error at the midpoints %.3f deg\n",
                  m.needle_interpolation_deg);
    os << buf;
  }
  for (const auto& s : m.skipped) os << "  not monitored: " << s << "\n";
  return os.str();
}

}  // namespace meter::convert
