// The greedy quality choice (greedy_choice.hpp).
#include "meter/engine/governor/greedy_choice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace meter::engine::governor {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double sane_scale(double s) { return std::isfinite(s) && s > 0 ? s : 1.0; }

UnitLevel level_at_rank(const UnitCosts& u, int rank) { return {rank % u.shadings, rank / u.shadings}; }
int rank_of(const UnitCosts& u, const UnitLevel& l) { return l.lod * u.shadings + l.shading; }

// Error of a unit level / rung relative to full quality; nullopt = not measured (level 0 and
// rung 0 are exact by definition).
std::optional<double> level_error(const UnitCosts& u, const UnitLevel& l) {
  if (l == UnitLevel{}) return 0.0;
  const LevelCost& c = u.at(l);
  if (!c.psnr_db) return std::nullopt;
  return relative_error(c.psnr_db);
}

std::optional<double> rung_error(const CostModel& m, int g) {
  if (g == 0) return 0.0;
  if (!m.globals[std::size_t(g)].psnr_db) return std::nullopt;
  return relative_error(m.globals[std::size_t(g)].psnr_db);
}

// How much a move is worth. Lowering: ms saved per unit of error added; raising: error bought
// back per ms spent. A move that adds no error (lowering) or costs no time (raising) is worth
// everything. nullopt: an error is not measured. ms: saved (lowering) or spent (raising).
std::optional<double> worth(double ms, std::optional<double> from_error, std::optional<double> to_error,
                            bool lowering) {
  if (!from_error || !to_error) return std::nullopt;
  if (lowering) {
    const double added = *to_error - *from_error;
    return added <= 0 ? kInf : ms / added;
  }
  const double bought = *from_error - *to_error;
  return ms <= 0 ? kInf : bought / ms;
}

// The frame being decided: the choice so far, each unit's pixels in the frame it will draw, and
// the prediction (kept as a running sum; recomputed in full when a rung changes).
class Working {
 public:
  Working(const CostModel& m, const FrameLoad& load, const FrameLoad* full, QualityChoice choice, ModelScale s)
      : m_(m), full_(full), choice_(std::move(choice)), scale_(s) {
    const std::size_t n = m.units.size();
    px_.resize(n);
    box_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      px_[i] = sane_pixels(load.unit_pixels[i]);
      box_[i] = full ? sane_pixels(full->unit_pixels[i]) : px_[i];
    }
    redrawn_ = sane_pixels(load.redrawn_pixels);
    g_ = std::max(0, global_rung(m, choice_.global));
    choice_.global = m.globals[std::size_t(g_)].level;
    total_ = total_at(g_);
  }

  const QualityChoice& choice() const { return choice_; }
  double total() const { return total_; }
  int rung() const { return g_; }
  // The unit's screen size for the paper's order: its whole box when the full frame is known.
  double size(std::size_t u) const { return full_ ? box_[u] : px_[u]; }
  bool movable(std::size_t u) const { return !m_.units[u].safety && (full_ != nullptr || px_[u] > 0); }

  // Change of the prediction if unit u were drawn at `level` (its whole box redrawn).
  double unit_delta(std::size_t u, const UnitLevel& level) const {
    const double moved_px = std::max(px_[u], box_[u]);
    return unit_ms(u, level, g_, moved_px) - unit_ms(u, choice_.units[u], g_, px_[u]);
  }
  void move_unit(std::size_t u, const UnitLevel& level) {
    total_ += unit_delta(u, level);
    px_[u] = std::max(px_[u], box_[u]);
    choice_.units[u] = level;
  }

  // The prediction at rung g: a rung change redraws the whole frame, so it is judged on the full
  // frame's load when known.
  double total_at(int g) const {
    const bool whole = g != g_ && full_ != nullptr;
    const GlobalCost& r = m_.globals[std::size_t(g)];
    const double redrawn = whole ? sane_pixels(full_->redrawn_pixels) : redrawn_;
    double t = scale_.pixel * m_.overhead.a_ms_per_pixel * redrawn * r.pixel_factor +
               scale_.fixed * (m_.overhead.b_ms + r.fixed_ms);
    for (std::size_t u = 0; u < px_.size(); ++u) t += unit_ms(u, choice_.units[u], g, whole ? std::max(px_[u], box_[u]) : px_[u]);
    return t;
  }
  void move_rung(int g) {
    if (g != g_ && full_ != nullptr) {
      for (std::size_t u = 0; u < px_.size(); ++u) px_[u] = std::max(px_[u], box_[u]);
      redrawn_ = sane_pixels(full_->redrawn_pixels);
    }
    g_ = g;
    choice_.global = m_.globals[std::size_t(g)].level;
    total_ = total_at(g);
  }

 private:
  double unit_ms(std::size_t u, const UnitLevel& l, int g, double pixels) const {
    return unit_parts(m_, int(u), l, g, pixels).total(scale_);
  }

  const CostModel& m_;
  const FrameLoad* full_;
  QualityChoice choice_;
  ModelScale scale_;
  std::vector<double> px_, box_;
  double redrawn_ = 0;
  int g_ = 0;
  double total_ = 0;
};

struct UnitMove {
  std::size_t unit = 0;
  UnitLevel level;
  double delta = 0;
};

// The paper's next step down: the first unit in `order` (smallest first) with a cheaper level
// of lower quality; its next such rank.
std::optional<UnitMove> unit_step_down(const CostModel& m, const Working& w, const std::vector<std::size_t>& order) {
  for (std::size_t u : order) {
    const UnitCosts& uc = m.units[u];
    const int ranks = uc.shadings * uc.lods;
    for (int r = rank_of(uc, w.choice().units[u]) + 1; r < ranks; ++r) {
      const UnitLevel l = level_at_rank(uc, r);
      const double d = w.unit_delta(u, l);
      if (d < 0) return UnitMove{u, l, d};
    }
  }
  return std::nullopt;
}

// The next step up: the first unit in `order` (largest first) with a better level that fits;
// its best such level.
std::optional<UnitMove> unit_step_up(const CostModel& m, const Working& w, const std::vector<std::size_t>& order,
                                     double budget) {
  for (std::size_t u : order) {
    const UnitCosts& uc = m.units[u];
    const int current = rank_of(uc, w.choice().units[u]);
    for (int r = 0; r < current; ++r) {
      const UnitLevel l = level_at_rank(uc, r);
      const double d = w.unit_delta(u, l);
      if (w.total() + d <= budget) return UnitMove{u, l, d};
    }
  }
  return std::nullopt;
}

// The next rung down (cheaper, after the current in quality order) or the best rung up that fits.
std::optional<int> rung_step(const CostModel& m, const Working& w, bool lowering, double budget) {
  const int n = int(m.globals.size());
  if (lowering) {
    for (int g = w.rung() + 1; g < n; ++g)
      if (w.total_at(g) < w.total()) return g;
  } else {
    for (int g = 0; g < w.rung(); ++g)
      if (w.total_at(g) <= budget) return g;
  }
  return std::nullopt;
}

// Whether the rung step is taken instead of the unit step (see the header).
bool prefer_rung(const CostModel& m, const Working& w, const std::optional<UnitMove>& unit, int rung, bool lowering) {
  if (!unit) return true;
  const std::size_t u = unit->unit;
  const UnitCosts& uc = m.units[u];
  const double rung_change = w.total_at(rung) - w.total();
  const auto unit_worth = worth(lowering ? -unit->delta : unit->delta, level_error(uc, w.choice().units[u]),
                                level_error(uc, unit->level), lowering);
  const auto rung_worth = worth(lowering ? -rung_change : rung_change, rung_error(m, w.rung()), rung_error(m, rung), lowering);
  if (!unit_worth || !rung_worth) return !lowering;  // unmeasured: rungs down last, up first
  return *rung_worth > *unit_worth;
}

// One step down (lowering) or up: the unit step in the paper's order or the rung step, whichever
// prefer_rung picks. False when neither exists.
bool take_step(const CostModel& m, Working& w, const std::vector<std::size_t>& order, double budget, bool lowering) {
  const auto unit = lowering ? unit_step_down(m, w, order) : unit_step_up(m, w, order, budget);
  const auto rung = rung_step(m, w, lowering, budget);
  if (rung && prefer_rung(m, w, unit, *rung, lowering))
    w.move_rung(*rung);
  else if (unit)
    w.move_unit(unit->unit, unit->level);
  else
    return false;
  return true;
}

QualityChoice normalised(const CostModel& m, const QualityChoice& current) {
  QualityChoice c = current;
  if (c.units.empty()) c.units.assign(m.units.size(), UnitLevel{});
  if (c.units.size() != m.units.size()) return c;  // predict_ms reports it
  for (std::size_t u = 0; u < m.units.size(); ++u)
    if (m.units[u].safety) c.units[u] = UnitLevel{};
  return c;
}

}  // namespace

QualityChoice full_quality(const CostModel& model) {
  QualityChoice c;
  if (!model.globals.empty()) c.global = model.globals[0].level;
  c.units.assign(model.units.size(), UnitLevel{});
  return c;
}

QualityChoice cheapest_quality(const CostModel& model) {
  QualityChoice c = full_quality(model);
  auto cheaper = [](double a1, double b1, double a2, double b2) { return a1 < a2 || (a1 == a2 && b1 <= b2); };
  for (std::size_t g = 1; g < model.globals.size(); ++g) {
    const GlobalCost& best = model.globals[std::size_t(global_rung(model, c.global))];
    if (cheaper(model.globals[g].pixel_factor, model.globals[g].fixed_ms, best.pixel_factor, best.fixed_ms))
      c.global = model.globals[g].level;
  }
  for (std::size_t u = 0; u < model.units.size(); ++u) {
    const UnitCosts& uc = model.units[u];
    if (uc.safety) continue;
    for (int r = 1; r < uc.shadings * uc.lods; ++r) {
      const LinearCost& now = uc.at(c.units[u]).cost;
      const UnitLevel l = level_at_rank(uc, r);
      if (cheaper(uc.at(l).cost.a_ms_per_pixel, uc.at(l).cost.b_ms, now.a_ms_per_pixel, now.b_ms)) c.units[u] = l;
    }
  }
  return c;
}

GreedyResult greedy_choice(const CostModel& model, const FrameLoad& load, const QualityChoice& current,
                           const GreedyBudget& budget, const ModelScale& scale, const FrameLoad* full_load) {
  if (model.globals.empty()) throw std::invalid_argument("greedy choice: the cost model has no global rung");
  QualityChoice start = normalised(model, current);
  if (global_rung(model, start.global) < 0) start.global = model.globals[0].level;
  // Validates the start choice and the loads against the model.
  const ModelScale s{sane_scale(scale.pixel), sane_scale(scale.fixed)};
  const double start_ms = predict_ms(model, load, start, s);
  if (!load.drawn) return {start, start_ms, false, false};
  if (full_load && (!full_load->drawn || full_load->unit_pixels.size() != model.units.size()))
    throw std::invalid_argument("greedy choice: the full frame's load does not have one entry per unit");

  Working w(model, load, full_load, std::move(start), s);
  std::vector<std::size_t> smallest_first;
  for (std::size_t u = 0; u < model.units.size(); ++u)
    if (w.movable(u)) smallest_first.push_back(u);
  std::stable_sort(smallest_first.begin(), smallest_first.end(),
                   [&](std::size_t a, std::size_t b) { return w.size(a) < w.size(b); });
  std::vector<std::size_t> largest_first = smallest_first;
  std::stable_sort(largest_first.begin(), largest_first.end(),
                   [&](std::size_t a, std::size_t b) { return w.size(a) > w.size(b); });

  GreedyResult result;
  if (w.total() > budget.trigger_ms)
    while (w.total() > budget.budget_ms && take_step(model, w, smallest_first, budget.budget_ms, true)) result.lowered = true;
  while (take_step(model, w, largest_first, budget.budget_ms, false)) result.raised = true;
  result.choice = w.choice();
  result.predicted_ms = w.total();
  return result;
}

}  // namespace meter::engine::governor
