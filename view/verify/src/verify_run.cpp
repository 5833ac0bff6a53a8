// The frame loop of meter-verify: per frames.csv row, the signal state the view drew with is
// rebuilt and run through the engine's BindingEvaluator, each region's expectation read from
// its outputs, and the row's PNG judged region by region.
#include <filesystem>
#include <memory>
#include <set>

#include "meter/engine/package_reader.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/verify/frames_table.hpp"
#include "meter/verify/verify.hpp"

namespace meter::verify {
namespace {

namespace fs = std::filesystem;

// One column group per bound signal (the first binding of each), as frames.csv writes them.
struct SignalColumns {
  std::string signal;
  protocol::SignalId id = 0;
};

std::vector<SignalColumns> signal_columns(const engine::Scene& scene, const FramesTable& t) {
  std::vector<SignalColumns> out;
  std::set<std::string> seen;
  for (const auto& b : scene.config.bindings) {
    if (!seen.insert(b.signal).second) continue;
    for (const auto& c : {b.signal, b.signal + ".status", b.signal + ".failsafe"}) {
      if (!t.has(c)) {
        throw VerifyError(t.file.string() + ":1: no column \"" + c + "\": this run was not drawn from this package's bindings");
      }
    }
    const auto id = engine::bound_signal_id(b);
    if (id) out.push_back({b.signal, *id});
  }
  return out;
}

// The state the view drew this row with. Every signal that has been Valid (in this row or an
// earlier one) first as Valid at its column's value, so a binding that holds its last value holds
// this one; then with the row's statuses and link, so the bindings' failsafes apply exactly where
// the view applied them. A signal never Valid yet stays without a value, as in the view (a lamp
// material then keeps its own colour). `ever_valid` carries over from row to row. `text_values`:
// each readout formats the value in its own <node>.value column (the needle of the same signal
// may lag behind it while smoothing).
// Needles: the value column is the value the needle drew, smoothed, also while it swings to its
// failsafe value, so a needle's state is that value as Valid (first step only) for every signal
// that was Valid before or whose needle has a failsafe value (else the needle rests).
enum class Replay { Drawn, Needles, Texts };

bool has_failsafe_needle(const engine::Scene& scene, const std::string& signal) {
  for (const auto& b : scene.config.bindings)
    if (b.kind == bridge::BindingKind::Animation && b.signal == signal && b.failsafe_value) return true;
  return false;
}

void replay_row(engine::BindingEvaluator& ev, const FramesTable& t, const FrameRow& row,
                const std::vector<SignalColumns>& signals, const engine::Scene& scene, Replay mode,
                std::set<protocol::SignalId>& ever_valid) {
  const bool text_values = mode == Replay::Texts;
  protocol::SignalTable valid, as_drawn;
  for (const auto& s : signals) {
    double v = number_cell(t, row, s.signal);
    if (text_values) {
      for (const auto& b : scene.config.bindings) {
        if (b.kind == bridge::BindingKind::Text && b.signal == s.signal && t.has(b.node + ".value")) v = number_cell(t, row, b.node + ".value");
      }
    }
    const auto& status_text = row.cells.at(s.signal + ".status");
    const auto status = protocol::status_from_string(status_text);
    if (!status) {
      throw VerifyError(t.file.string() + ":" + std::to_string(row.line) + ": column " + s.signal + ".status: \"" +
                        status_text + "\" is not a signal status");
    }
    if (*status == protocol::SignalStatus::Valid && row.link_up) ever_valid.insert(s.id);
    if (ever_valid.count(s.id) || (mode == Replay::Needles && has_failsafe_needle(scene, s.signal))) {
      valid.set(s.id, {v, protocol::SignalStatus::Valid, ""});
    }
    as_drawn.set(s.id, {v, *status, ""});
  }
  ev.update(valid, true, -1.0);
  if (mode != Replay::Needles) ev.update(as_drawn, row.link_up, -1.0);
}

engine::RgbaView view_of(const platform::Image& img) { return {img.rgba.data(), img.width, img.height, 0, 0, 0}; }

}  // namespace

std::size_t VerifyReport::failures() const {
  std::size_t n = 0;
  for (const auto& c : checks) n += c.checked && !c.verdict.ok;
  return n;
}

VerifyReport verify_run(const VerifyOptions& o) {
  if (!fs::exists(o.package)) throw VerifyError(o.package + ": no such scene package");
  const engine::Scene scene = engine::read_package(o.package);
  const auto& table = scene.integrity;
  if (table.empty()) {
    throw VerifyError(o.package + ": the package has no integrity table (no telltale, needle or readout was measured; "
                      "convert it with meter-convert --integrity=egl)");
  }
  if (!fs::is_directory(o.run_dir)) throw VerifyError(o.run_dir + ": not a run folder");
  const FramesTable frames = read_frames_table(fs::path(o.run_dir) / "frames.csv");
  const auto signals = signal_columns(scene, frames);
  for (const auto& r : frames.rows) {
    if (!fs::exists(fs::path(o.run_dir) / r.png)) {
      throw VerifyError(frames.file.string() + ":" + std::to_string(r.line) + ": frame " + std::to_string(r.frame) +
                        ": its PNG " + r.png + " is not in " + o.run_dir);
    }
  }
  bool readouts = false;
  for (const auto& g : table.regions) readouts = readouts || g.kind == bridge::SafetyKind::Readout;
  // The readouts' reference: the engine drawing the frame's state (on the chosen backend).
  std::unique_ptr<platform::GpuBackend> backend;
  std::unique_ptr<engine::Renderer> reference;
  if (readouts) {
    const auto kind = platform::parse_backend_kind(o.backend);
    if (!kind) throw VerifyError("--backend: unknown backend \"" + o.backend + "\" (egl or osmesa)");
    backend = platform::create_backend(*kind);
    engine::RendererOptions ro;
    ro.msaa = o.msaa;
    reference = std::make_unique<engine::Renderer>(*backend, scene, ro);
  }
  engine::BindingEvaluator drawn(scene), needles(scene), texts(scene);
  std::set<protocol::SignalId> ever_valid, ever_valid_needles, ever_valid_texts;
  VerifyReport report;
  report.package = o.package, report.run_dir = o.run_dir, report.frames = frames.rows.size();
  for (const auto& row : frames.rows) {
    const auto img = platform::read_png(fs::path(o.run_dir) / row.png);
    if (img.width != table.width || img.height != table.height) {
      throw VerifyError(row.png + ": the frame is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                        ", the package's integrity table is for " + std::to_string(table.width) + "x" +
                        std::to_string(table.height) + " (the run used meter-view --size)");
    }
    replay_row(drawn, frames, row, signals, scene, Replay::Drawn, ever_valid);
    replay_row(needles, frames, row, signals, scene, Replay::Needles, ever_valid_needles);
    auto expected = engine::expected_states(table, scene, drawn);
    const auto needle_expected = engine::expected_states(table, scene, needles);
    for (std::size_t i = 0; i < table.regions.size(); ++i) {
      if (table.regions[i].kind == bridge::SafetyKind::Needle) expected[i] = needle_expected[i];
    }
    const platform::Image* ref = nullptr;
    if (readouts) {
      replay_row(texts, frames, row, signals, scene, Replay::Texts, ever_valid_texts);
      const auto with_texts = engine::expected_states(table, scene, texts);
      auto outputs = drawn.outputs();
      outputs.texts = texts.outputs().texts;
      outputs.animation_time = needles.outputs().animation_time;
      reference->apply(outputs);
      reference->render(false, true);
      ref = &reference->last_image();
      for (std::size_t i = 0; i < table.regions.size(); ++i) {
        if (table.regions[i].kind == bridge::SafetyKind::Readout) expected[i] = with_texts[i];
      }
    }
    const auto ref_view = ref ? view_of(*ref) : engine::RgbaView{};
    for (std::size_t i = 0; i < table.regions.size(); ++i) {
      const auto& g = table.regions[i];
      CheckResult c;
      c.frame = row.frame, c.png = row.png, c.region = g.name, c.kind = g.kind;
      c.checked = expected[i].known;
      if (c.checked) c.verdict = engine::check_region(g, view_of(img), expected[i], ref ? &ref_view : nullptr);
      report.checks.push_back(std::move(c));
    }
  }
  return report;
}

}  // namespace meter::verify
