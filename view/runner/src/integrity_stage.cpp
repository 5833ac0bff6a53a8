#include "meter/runner/integrity_stage.hpp"

#include <algorithm>
#include <charconv>

#include "meter/protocol/wire.hpp"
#include "meter/runner/view_error.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {

namespace {

std::uint64_t frame_number(const std::string& text, const std::string& whole) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size())
    throw ViewError("--inject-fault " + whole + ": \"" + text + "\" is not a frame number (expected digits)");
  return v;
}

}  // namespace

FaultSchedule parse_fault_schedule(const std::string& text, const engine::Scene& scene, int height) {
  const auto at = text.find('@');
  if (at == std::string::npos)
    throw ViewError("--inject-fault " + text + ": expected KIND[:REGION]@FIRST[-LAST], e.g. drop:TT_ABS@30");
  const std::string what = text.substr(0, at), frames = text.substr(at + 1);
  const auto colon = what.find(':');
  const std::string kind_text = what.substr(0, colon), region = colon == std::string::npos ? "" : what.substr(colon + 1);
  FaultSchedule s;
  s.display_copy_lost = kind_text == "display";
  const auto kind = s.display_copy_lost ? std::optional(engine::FaultKind::StuckFrame) : engine::parse_fault_kind(kind_text);
  if (!kind)
    throw ViewError("--inject-fault " + text + ": unknown fault \"" + kind_text +
                    "\" (expected drop, colour, cover, text, stuck, needle or display)");
  s.fault.kind = *kind;
  if (*kind != engine::FaultKind::StuckFrame) {
    const auto& regions = scene.integrity.regions;
    const auto it = std::find_if(regions.begin(), regions.end(), [&](const auto& r) { return r.name == region; });
    if (it == regions.end())
      throw ViewError("--inject-fault " + text + ": no safety region \"" + region + "\" in " + scene.source_name +
                      " (meter-convert --report lists them)");
    s.fault.node = scene.find_node(it->node);
    if (s.fault.node < 0)
      throw ViewError("--inject-fault " + text + ": region \"" + region + "\" names node \"" + it->node +
                      "\", which " + scene.source_name + " does not have");
    s.fault.box = platform::PixelRegion{it->rect.x, height - it->rect.y - it->rect.height, it->rect.width, it->rect.height};
  }
  const auto dash = frames.find('-');
  s.first = frame_number(frames.substr(0, dash), text);
  if (dash != std::string::npos) {
    s.last = frame_number(frames.substr(dash + 1), text);
    if (*s.last < s.first) throw ViewError("--inject-fault " + text + ": the last frame is before the first");
  }
  return s;
}

bool FaultLogLimit::admit(const std::string& region, Clock::time_point now) {
  const bool first = std::find(seen_.begin(), seen_.end(), region) == seen_.end();
  if (first) seen_.push_back(region);
  if (first || !last_ || now - *last_ >= std::chrono::seconds(1)) {
    last_ = now;
    return true;
  }
  ++suppressed_;
  return false;
}

IntegrityStage::IntegrityStage(RenderContext& ctx, const ViewOptions& options, ViewHealth& health, std::ostream& log)
    : ctx_(ctx), health_(health), log_(log),
      monitor_(ctx.scene, ctx.renderer.width(), ctx.renderer.height(), options.integrity_monitor) {
  if (monitor_.on()) {
    log << "meter-view: integrity monitor on: " << monitor_.table().regions.size() << " safety regions\n";
  } else if (!ctx.scene.integrity.empty()) {
    log << "meter-view: integrity monitor off: " << monitor_.off_reason() << "\n";
  }
  if (!options.inject_fault.empty()) {
    schedule_ = parse_fault_schedule(options.inject_fault, ctx.scene, ctx.renderer.height());
    protocol::LogLine(log, protocol::LogLevel::Warning, "integrity") << "meter-view: TEST FAULT INJECTION: " << options.inject_fault << "\n";
  }
}

void IntegrityStage::before_frame(std::uint64_t frame) {
  monitor_.prepare(ctx_.renderer, ctx_.pipeline.evaluator(), !on_display_);
  if (!schedule_ || schedule_->display_copy_lost) return;
  if (frame == schedule_->first) ctx_.renderer.inject(schedule_->fault);
  if (schedule_->last && frame == *schedule_->last + 1) ctx_.renderer.inject(std::nullopt);
}

void IntegrityStage::after_frame(std::uint64_t frame, Clock::time_point now, const RegionReader* reader) {
  if (!monitor_.on()) return;
  const auto& faults = monitor_.check(ctx_.renderer, ctx_.pipeline.evaluator(), reader);
  cells_.faults = faults.size();
  cells_.total = monitor_.faults();
  cells_.first = faults.empty() ? std::string() : faults.front().describe();
  if (faults.empty()) return;
  health_.report(protocol::kViewFaultIntegrity, now);
  if (!first_fault_frame_) first_fault_frame_ = frame;
  for (const auto& f : faults)
    if (limit_.admit(f.region, now)) protocol::LogLine(log_, protocol::LogLevel::Error, "integrity", {protocol::log_field("frame", static_cast<std::int64_t>(frame)), protocol::log_field("region", f.region), protocol::log_field("fault", "integrity")}) << "meter-view: integrity fault at frame " << frame << ": " << f.describe() << "\n";
}

void IntegrityStage::summary(std::ostream& log) const {
  if (!monitor_.on()) return;
  log << "meter-view: integrity: " << monitor_.frames_checked() << " frames checked, " << monitor_.faults() << " faults ("
      << monitor_.frozen_faults() << " frozen), " << monitor_.safe_redraws() << " safe-path redraws";
  if (first_fault_frame_) log << ", first at frame " << *first_fault_frame_;
  if (limit_.suppressed()) log << ", " << limit_.suppressed() << " fault lines not logged";
  log << "\n";
}

}  // namespace meter::runner
