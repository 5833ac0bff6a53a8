#include "meter/runner/governed_frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "meter/engine/governor/cost_file.hpp"
#include "meter/engine/governor/warm_up_choices.hpp"
#include "meter/protocol/trace_events.hpp"
#include "meter/runner/view_error.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {
namespace gov = engine::governor;
namespace {

gov::CostModel read_costs(const std::string& path, std::span<const gov::UnitLadder> ladders, const std::string& scene) {
  std::ifstream in(path);
  if (!in) {
    throw ViewError(path + ": no cost file for the frame-rate governor (--target-ms, --quality cheapest); make it with "
                    "`meter-calibrate " + scene + "` or give --costs FILE");
  }
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return gov::bind_costs(gov::parse_costs(text.str(), path), ladders, path);
  } catch (const std::invalid_argument& e) {
    throw ViewError(std::string(e.what()) + " (run meter-calibrate again for this package)");
  }
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::lround(p * static_cast<double>(v.size() - 1)))];
}

std::string ms_text(double ms) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", ms);
  return b;
}

}  // namespace

std::string default_costs_path(const std::string& package) { return package + ".costs.json"; }

CostInjection parse_cost_injection(const std::string& text) {
  const auto fail = [&] {
    return ViewError("--inject-cost: expected NS_PER_PIXEL@FIRST-LAST (e.g. 50@20-80), got \"" + text + "\"");
  };
  CostInjection c;
  const auto at = text.find('@'), dash = text.find('-', at == std::string::npos ? 0 : at);
  if (at == std::string::npos || dash == std::string::npos) throw fail();
  try {
    std::size_t used = 0;
    c.ns_per_pixel = std::stod(text.substr(0, at), &used);
    if (used != at || !(c.ns_per_pixel > 0) || !std::isfinite(c.ns_per_pixel)) throw fail();
    const std::string first = text.substr(at + 1, dash - at - 1), last = text.substr(dash + 1);
    if (first.empty() || last.empty() || first.find_first_not_of("0123456789") != std::string::npos ||
        last.find_first_not_of("0123456789") != std::string::npos)
      throw fail();
    c.first = std::stoull(first), c.last = std::stoull(last);
  } catch (const std::logic_error&) {
    throw fail();
  }
  if (c.last < c.first) throw fail();
  return c;
}

GovernedFrames::GovernedFrames(engine::Renderer& renderer, const ViewOptions& options, std::ostream& log)
    : renderer_(renderer), log_(&log), target_ms_(options.target_ms), start_(Clock::now()), last_print_(start_) {
  if (!options.inject_cost.empty()) {
    inject_ = parse_cost_injection(options.inject_cost);
    protocol::LogLine(log, protocol::LogLevel::Warning, "governor") << "meter-view: TEST COST INJECTION: " << options.inject_cost << " (ns per drawn pixel @ frames)\n";
  }
  if (options.stats && options.stats_interval_s > 0)
    interval_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.stats_interval_s));
  const bool off = options.governor == "off";
  if (!options.governor.empty() && !off && options.governor != "on")
    throw ViewError("--governor: expected on or off, got \"" + options.governor + "\"");
  if (!options.quality.empty() && options.quality != "full" && options.quality != "cheapest")
    throw ViewError("--quality: expected full or cheapest, got \"" + options.quality + "\"");
  if (options.governor == "on" && !(options.target_ms > 0)) throw ViewError("--governor on needs --target-ms");
  if (!options.quality.empty() && options.governor == "on")
    throw ViewError("--quality " + options.quality + " fixes the quality: it cannot go with --governor on");
  const bool on = options.target_ms > 0 && !off && options.quality.empty();
  if (!on && options.quality != "cheapest") return;  // full quality, as without a governor
  const std::string path = options.costs.empty() ? default_costs_path(options.scene_path) : options.costs;
  gov::CostModel model = read_costs(path, renderer.draw_units(), options.scene_path);
  if (!on) {  // --quality cheapest: fixed from the first frame on
    renderer.set_quality(gov::cheapest_quality(model));
    log << "meter-view: fixed quality: the cheapest the cost file " << path << " predicts\n";
    return;
  }
  gov::GovernorOptions go;
  go.target_ms = options.target_ms;
  governor_.emplace(std::move(model), go);
  log << "meter-view: frame-rate governor on: target " << options.target_ms << " ms, " << renderer.draw_units().size()
      << " draw units, costs " << path << "\n";
}

std::optional<gov::QualityChoice> GovernedFrames::choose(const gov::FrameLoad& planned) {
  if (!governor_ || drawn_ == 0) return std::nullopt;  // off, or the start-up frame
  return governor_->choose(planned);
}

void GovernedFrames::rendered(const engine::FrameTiming& timing, std::int64_t began_ns) {
  const std::uint64_t frame = frame_++;
  const bool start_up = drawn_ == 0;
  if (inject_ && timing.drawn && frame >= inject_->first && frame <= inject_->last) {
    const float s = renderer_.quality().global.scale;
    const double pixels = renderer_.last_load().redrawn_pixels * double(s) * double(s);
    const auto until = Clock::now() + std::chrono::nanoseconds(std::llround(pixels * inject_->ns_per_pixel));
    while (Clock::now() < until) {
    }
  }
  const double ms = double(protocol::monotonic_ns(Clock::now()) - began_ns) / 1e6;
  if (governor_ && start_up && timing.drawn) warm_up(ms);
  if (!timing.drawn) return;
  ++drawn_;
  if (interval_ != Clock::duration::zero()) window_ms_.push_back(ms);
  if (target_ms_ > 0 && ms > target_ms_) ++over_, ++window_over_;
  if (governor_ && !start_up) observe(ms);
}

// Every level the governor may take drawn once now, with the outputs the display shows, so none
// costs its first-use work (program compiles, the driver's shader variants, text sizes) on a
// governed frame. The held rung and the one drawn before it keep their targets and static layer;
// the renderer releases the other rungs' (memory), which a later visit makes again.
void GovernedFrames::warm_up(double start_up_ms) {
  const auto w0 = Clock::now();
  const int frames = renderer_.warm_up(gov::warm_up_choices(governor_->model()));
  *log_ << "meter-view: governor warm-up after the start-up frame: " << frames << " frames at its levels in "
        << ms_text(std::chrono::duration<double, std::milli>(Clock::now() - w0).count()) << " ms\n";
  // Its frames.csv / trace cells: drawn at the run's starting quality, no prediction made.
  cells_.predicted_ms = 0.0, cells_.measured_ms = start_up_ms;
  cells_.msaa = renderer_.quality().global.msaa, cells_.scale = renderer_.quality().global.scale;
}

void GovernedFrames::observe(double ms) {
  governor_->observe(renderer_.last_load(), renderer_.quality(), ms);
  const gov::QualityChoice& now = governor_->current();
  cells_.predicted_ms = governor_->predicted_ms(), cells_.measured_ms = ms;
  cells_.msaa = now.global.msaa, cells_.scale = now.global.scale;
  if (described_ != now) {  // the units below full quality, named only when the choice changed
    const gov::GovernorState st = governor_->state();
    cells_.units_reduced = st.reduced.size(), cells_.reduced = gov::reduced_summary(st);
    described_ = now;
  }
}

void GovernedFrames::print_if_due(Clock::time_point now, std::ostream& log) {
  if (interval_ == Clock::duration::zero() || now - last_print_ < interval_ || target_ms_ <= 0) return;
  char when[32];
  std::snprintf(when, sizeof when, "%.1f", std::chrono::duration<double>(now - start_).count());
  log << "meter-view: governor " << when << " s: " << window_ms_.size() << " frames drawn, " << window_over_ << " over the "
      << target_ms_ << " ms target, measured p50 " << ms_text(percentile(window_ms_, 0.5)) << " max "
      << ms_text(percentile(window_ms_, 1.0)) << " ms";
  if (governor_) {
    const auto st = governor_->state();
    log << "; last frame predicted " << ms_text(cells_.predicted_ms) << " measured " << ms_text(cells_.measured_ms)
        << " ms; model scale pixel " << ms_text(st.scale.pixel) << " fixed " << ms_text(st.scale.fixed)
        << (st.fast_attack > 1.0 ? " (fast attack x" + ms_text(st.fast_attack) + ")" : std::string())
        << (st.spread > 1.0 ? "; spread x" + ms_text(st.spread) : std::string()) << "; MSAA " << st.global.msaa
        << " scale " << st.global.scale << "; " << st.reduced.size() << " units below full quality"
        << (st.reduced.empty() ? "" : ": " + cells_.reduced)
        << (st.readback_reserved ? "; readback " + ms_text(st.readback_ms) + " ms reserved" : std::string());
  }
  log << "\n";
  window_ms_.clear();
  window_over_ = 0;
  last_print_ = now;
}

void GovernedFrames::summary(std::ostream& log) const {
  if (target_ms_ <= 0) return;
  log << "meter-view: target " << target_ms_ << " ms: " << drawn_ << " frames drawn, " << over_ << " over it ("
      << ms_text(drawn_ ? 100.0 * double(over_) / double(drawn_) : 0.0) << " %)";
  if (governor_) {
    const auto st = governor_->state();
    log << "; governor: " << st.changes << " quality changes (" << st.step_ups_undone
        << " step ups undone), at exit MSAA " << st.global.msaa << " scale " << st.global.scale
        << ", " << (st.reduced.empty() ? std::string("every unit at full quality") : gov::reduced_summary(st));
  } else {
    log << "; governor off";
  }
  log << "\n";
}

}  // namespace meter::runner
