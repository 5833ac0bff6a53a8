#include "meter/runner/presentation_rows.hpp"

#include <utility>

#include "meter/protocol/trace_events.hpp"

namespace meter::runner {

bool PresentationRows::fate(std::uint64_t frame, std::optional<platform::PresentedFrame>& shown) const {
  if (const auto it = fates_.find(frame); it != fates_.end()) {
    shown = it->second;
    return true;
  }
  shown.reset();
  return done_ || (through_ && frame <= *through_);
}

void PresentationRows::add(std::uint64_t frame, std::string text, std::int64_t render_ended_ns, std::int64_t now_ns,
                           const Write& write) {
  Row row{frame, std::move(text), render_ended_ns, now_ns, false, std::nullopt};
  row.known = fate(frame, row.shown);
  rows_.push_back(std::move(row));
  expire(now_ns);
  release(write);
}

void PresentationRows::tell(std::uint64_t frame, const std::optional<platform::PresentedFrame>& shown,
                            std::int64_t now_ns, const Write& write) {
  fates_[frame] = shown;
  while (fates_.size() > kFates) fates_.erase(fates_.begin());
  for (Row& r : rows_) {
    if (r.frame == frame) r.known = true, r.shown = shown;
  }
  expire(now_ns);
  release(write);
}

void PresentationRows::presented(const platform::PresentedFrame& shown, std::int64_t now_ns, const Write& write) {
  if (!through_ || shown.frame > *through_) through_ = shown.frame;
  for (Row& r : rows_) r.known = r.known || r.frame < shown.frame;
  tell(shown.frame, shown.discarded ? std::nullopt : std::optional(shown), now_ns, write);
}

void PresentationRows::not_presented(std::uint64_t frame, std::int64_t now_ns, const Write& write) {
  tell(frame, std::nullopt, now_ns, write);
}

void PresentationRows::expire(std::int64_t now_ns) {
  for (Row& r : rows_) {
    if (now_ns - r.added_ns >= hold_ns_) r.known = true;
  }
}

void PresentationRows::done(const Write& write) {
  done_ = true;
  for (Row& r : rows_) r.known = true;
  release(write);
}

void PresentationRows::release(const Write& write) {
  while (!rows_.empty() && rows_.front().known) {
    const Row r = std::move(rows_.front());
    rows_.pop_front();
    write(r.text, r.render_ended_ns, r.shown ? &*r.shown : nullptr);
  }
}

void PresentationHeldCsv::on_presented(const platform::PresentedFrame& shown) {
  if (holding_) rows_.presented(shown, protocol::monotonic_now_ns(), writer());
}

void PresentationHeldCsv::not_presented(std::uint64_t frame) {
  if (holding_) rows_.not_presented(frame, protocol::monotonic_now_ns(), writer());
}

void PresentationHeldCsv::presentation_done() {
  if (holding_) rows_.done(writer());
}

void PresentationHeldCsv::hold(std::uint64_t frame, std::string text, std::int64_t render_ended_ns) {
  rows_.add(frame, std::move(text), render_ended_ns, protocol::monotonic_now_ns(), writer());
}

}  // namespace meter::runner
