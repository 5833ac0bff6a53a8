#include "meter/controller/conditioning.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace meter::controller {

// ---------------------------------------------------------------- needle

NeedleFilter::NeedleFilter(double tau) {
  if (!(tau > 0) || !std::isfinite(tau)) throw std::invalid_argument("needle time constant must be > 0 s");
  w_ = 1.0 / tau;
}

void NeedleFilter::reset(double value) {
  if (!std::isfinite(value)) return;
  x_ = value;
  v_ = 0;
  init_ = true;
}

double NeedleFilter::step(double target, double dt) {
  if (!std::isfinite(target)) return x_;
  if (!init_) {
    reset(target);
    return x_;
  }
  if (!(dt > 0) || !std::isfinite(dt)) return x_;  // dt = 0 (or garbage): nothing moves
  // e(t) = (e0 + (v0 + w e0) t) exp(-w t),  v(t) = (v0 - w (v0 + w e0) t) exp(-w t).
  // For huge w*t exp() underflows to 0 and t*0 = 0: the needle is simply at the target.
  const double e0 = x_ - target;
  const double k = v_ + w_ * e0;
  const double wt = w_ * dt;
  const double decay = wt > 700 ? 0.0 : std::exp(-wt);
  double e = (e0 + k * dt) * decay;
  double v = (v_ - w_ * k * dt) * decay;
  if (!std::isfinite(e) || !std::isfinite(v)) {
    e = 0;
    v = 0;
  }
  if (e0 != 0 && (e > 0) != (e0 > 0) && e != 0) {  // would cross the target: stop on it
    e = 0;
    v = 0;
  }
  x_ = target + e;
  v_ = v;
  return x_;
}

// ---------------------------------------------------------------- R39

double SpeedometerRule::apply(double displayed, double truth) const {
  if (!std::isfinite(truth) || truth < 0) truth = 0;
  if (!std::isfinite(displayed)) displayed = truth;
  double shown = displayed * ratio + offset_kmh;
  const double lo = truth, hi = truth * 1.1 + 4.0;
  if (shown < lo) shown = lo;
  if (shown > hi) shown = hi;
  return shown;
}

// ---------------------------------------------------------------- fuel

void FuelFilter::step(double level, bool valid, double speed, double dt) {
  if (!(dt >= 0) || !std::isfinite(dt)) dt = 0;
  bool plausible = valid && std::isfinite(level) && level >= c_.plausible_min && level <= c_.plausible_max;
  if (!plausible) {
    bad_for_ += dt;
    if (bad_for_ >= c_.fault_time_s) fault_ = true;
    return;
  }
  bad_for_ = 0;
  level = std::clamp(level, 0.0, 100.0);
  if (!init_ || fault_) {  // first value, or recovering from a sender fault: show the truth at once
    y_ = level;
    init_ = true;
    fault_ = false;
    rise_for_ = 0;
    return;
  }
  bool stopped = std::isfinite(speed) && speed < c_.stopped_below_kmh;
  if (stopped && level - y_ >= c_.refuel_delta) {
    rise_for_ += dt;
    if (rise_for_ >= c_.refuel_confirm_s) {
      y_ = level;
      rise_for_ = 0;
      ++refuels_;
      return;
    }
  } else {
    rise_for_ = 0;
  }
  const double tau = stopped ? c_.tau_stopped_s : c_.tau_moving_s;
  y_ += (level - y_) * (1.0 - std::exp(-dt / tau));
}

// ---------------------------------------------------------------- odometer

void Odometer::add_speed(double speed_kmh, std::int64_t dt_ns) {
  if (!(speed_kmh > 0) || !std::isfinite(speed_kmh) || dt_ns <= 0) return;
  // km/h * ns / 3600 = micrometres. The product v * dt is an integer for any speed with the
  // resolution a DBC gives it (0.01 km/h * 1e6 ns...), so it is counted in integer units of 1/3600
  // um and carried exactly: no rounding drift however long the car drives.
  const double product = std::nearbyint(speed_kmh * static_cast<double>(dt_ns));
  if (!(product < 9.0e18)) return;  // a glitch of absurd size: refuse rather than overflow
  const std::int64_t units = static_cast<std::int64_t>(product) + rem_;
  const std::int64_t add = units / 3600;
  rem_ = units % 3600;
  odo_um_ += add;
  trip_um_ += add;
}

void Odometer::add_counter(std::uint64_t counter, unsigned bits, double um_per_count) {
  const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
  counter &= mask;
  if (last_counter_) {
    std::uint64_t delta = (counter - *last_counter_) & mask;  // wraps correctly
    double um = static_cast<double>(delta) * um_per_count + carry_;
    // A NaN or negative scale, or a jump too large for int64, would reach an undefined double ->
    // int64 conversion (or count backwards): latch the counter and add nothing.
    if (!(um >= 0 && um < 9.0e18)) {
      last_counter_ = counter;
      return;
    }
    double whole = std::floor(um);
    carry_ = um - whole;
    odo_um_ += static_cast<std::int64_t>(whole);
    trip_um_ += static_cast<std::int64_t>(whole);
  }
  last_counter_ = counter;
}

namespace {
std::uint32_t crc32(const std::string& s) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}
}  // namespace

OdometerStore::OdometerStore(std::string dir) : dir_(std::move(dir)), path_(dir_ + "/odometer.state") {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("state dir " + dir_ + ": " + ec.message());
}

std::string OdometerStore::format(const OdometerRecord& r) {
  std::string body = "meter-odometer 1\nodo_um " + std::to_string(r.odo_um) + "\ntrip_um " +
                     std::to_string(r.trip_um) + "\nseq " + std::to_string(r.sequence) + "\n";
  char crc[32];
  std::snprintf(crc, sizeof crc, "crc %08x\n", crc32(body));
  return body + crc;
}

std::optional<OdometerRecord> OdometerStore::parse(const std::string& text, std::string* why) {
  auto fail = [&](const std::string& w) -> std::optional<OdometerRecord> {
    if (why) *why = w;
    return std::nullopt;
  };
  auto crc_pos = text.rfind("crc ");
  if (crc_pos == std::string::npos) return fail("no 'crc' line (truncated file)");
  std::string body = text.substr(0, crc_pos);
  unsigned long want = std::strtoul(text.c_str() + crc_pos + 4, nullptr, 16);
  if (crc32(body) != want) return fail("CRC mismatch (damaged file)");
  std::istringstream in(body);
  std::string magic, key;
  int version = 0;
  in >> magic >> version;
  if (magic != "meter-odometer" || version != 1) return fail("expected 'meter-odometer 1' header");
  OdometerRecord r;
  if (!(in >> key >> r.odo_um) || key != "odo_um") return fail("expected 'odo_um <integer>'");
  if (!(in >> key >> r.trip_um) || key != "trip_um") return fail("expected 'trip_um <integer>'");
  if (!(in >> key >> r.sequence) || key != "seq") return fail("expected 'seq <integer>'");
  if (r.odo_um < 0 || r.trip_um < 0) return fail("negative distance");
  return r;
}

std::optional<OdometerRecord> OdometerStore::load() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string why;
  auto r = parse(ss.str(), &why);
  if (!r) throw std::runtime_error(path_ + ": " + why);
  return r;
}

void OdometerStore::save(const OdometerRecord& r) {
  const std::string text = format(r);
  const std::string tmp = path_ + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(tmp + ": " + std::strerror(errno));
  std::size_t off = 0;
  while (off < text.size()) {
    ssize_t n = ::write(fd, text.data() + off, text.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      int e = errno;
      ::close(fd);
      throw std::runtime_error(tmp + ": write: " + std::strerror(e));
    }
    off += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    int e = errno;
    ::close(fd);
    throw std::runtime_error(tmp + ": fsync: " + std::strerror(e));
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path_.c_str()) != 0) throw std::runtime_error(path_ + ": rename: " + std::strerror(errno));
  // The rename itself must reach the disk, or a crash could bring the old name back.
  int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

// ---------------------------------------------------------------- telltales

bool BlinkPattern::lit(std::int64_t t, std::int64_t t_on) const {
  if (t < t_on) return false;
  if (!(period_s > 0) || period_s > 1e6) return true;  // no sensible period: steady
  const auto period = static_cast<std::int64_t>(period_s * 1e9);
  if (period <= 0) return true;
  const std::int64_t phase = (t - t_on) % period;
  return static_cast<double>(phase) < duty * static_cast<double>(period);
}

BulbCheck::BulbCheck(double d) {
  if (!(d >= 2.0 && d <= 4.0)) throw std::invalid_argument("bulb check duration must be 2..4 s, got " + std::to_string(d));
  dur_ns_ = static_cast<std::int64_t>(d * 1e9);
}

SeatBeltReminder::SeatBeltReminder(SeatBeltConfig c) : c_(c) {
  if (!(c.first_level_s >= 4.0 && c.first_level_s <= 8.0))
    throw std::invalid_argument("seat-belt first-level warning must last 4..8 s, got " + std::to_string(c.first_level_s));
}

bool SeatBeltReminder::lit(std::int64_t t, bool unbuckled, double speed) {
  if (!ign_ || !unbuckled) {
    second_ = false;
    return false;
  }
  if (!std::isfinite(speed)) speed = 0;
  if (speed > c_.second_level_kmh) {
    if (!second_) {
      second_ = true;
      second_since_ = t;
    }
    return c_.second_level_blink.lit(t, second_since_);
  }
  second_ = false;
  if (t - ign_on_ < static_cast<std::int64_t>(c_.first_level_s * 1e9)) return true;
  return speed > c_.speed_on_kmh;
}

bool Hysteresis::update(double v) {
  if (!std::isfinite(v)) return state;
  if (below) {
    if (v < on) state = true;
    else if (v > off) state = false;
  } else {
    if (v > on) state = true;
    else if (v < off) state = false;
  }
  return state;
}

}  // namespace meter::controller
