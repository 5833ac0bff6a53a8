// Correctness against independent references: the golden vectors (cantools' test expectations,
// cross-checked with canmatrix) and the ft86 log statistics produced by canmatrix.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/candump_line.hpp"

using namespace meter::controller;

namespace {

const std::string kShared = METER_SHARED_DIR;

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool q = false;
  for (char c : line) {
    if (c == '"') q = !q;
    else if (c == ',' && !q) {
      out.push_back(cur);
      cur.clear();
    } else cur += c;
  }
  out.push_back(cur);
  return out;
}

std::vector<std::uint8_t> hex_bytes(const std::string& h) {
  std::vector<std::uint8_t> b;
  for (std::size_t i = 0; i + 1 < h.size(); i += 2) b.push_back(static_cast<std::uint8_t>(std::stoul(h.substr(i, 2), nullptr, 16)));
  return b;
}

// Half a unit in the last printed digit: the expectation is as exact as it was written.
double tolerance_of(const std::string& number) {
  auto dot = number.find('.');
  if (dot == std::string::npos) return 0.5;
  return 0.5 * std::pow(10.0, -static_cast<double>(number.size() - dot - 1));
}

}  // namespace

TEST(Golden, EveryRowOfGoldenVectors) {
  std::ifstream in(kShared + "/data/can/dbc_semantics/golden_vectors.csv");
  ASSERT_TRUE(in) << "golden_vectors.csv missing under " << kShared;
  std::string line;
  std::getline(in, line);  // header
  int rows = 0, checked_values = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    auto col = split_csv(line);
    ASSERT_GE(col.size(), 5u) << line;
    SCOPED_TRACE(line);
    ++rows;
    Database db = load_dbc(kShared + "/data/can/dbc_semantics/" + col[0]);
    const DbcMessage* by_name = db.find(col[1]);
    ASSERT_NE(by_name, nullptr) << col[1];
    // The frame id column may name the id on the bus (J1939: differs from the DBC id).
    const DbcMessage* m = by_name;
    if (!col[2].empty()) {
      std::uint32_t id = static_cast<std::uint32_t>(std::stoul(col[2].substr(0, col[2].find(' ')), nullptr, 16));
      bool ext = id > 0x7FF;
      m = db.find(id & 0x1FFFFFFFu, ext);
      ASSERT_EQ(m, by_name) << "frame id " << col[2] << " must resolve to " << col[1];
    }
    auto payload = hex_bytes(col[3]);
    std::vector<DecodedSignal> out;
    decode(*m, payload, out);
    auto find = [&](const std::string& name) { return find_decoded(*m, out, name); };
    const std::string& expect = col[4];
    if (expect.find("must be shown invalid") != std::string::npos) {
      std::string name = expect.substr(0, expect.find(' '));
      auto* d = find(name);
      ASSERT_NE(d, nullptr) << name;
      EXPECT_NE(d->status, DecodeStatus::Valid) << name << " raw " << d->raw;
      EXPECT_EQ(d->status, DecodeStatus::NotAvailable);
      ++checked_values;
      continue;
    }
    std::stringstream ss(expect);
    std::string item;
    while (std::getline(ss, item, ';')) {
      auto eq = item.find('=');
      ASSERT_NE(eq, std::string::npos) << item;
      std::string name = item.substr(0, eq);
      std::string rest = item.substr(eq + 1);
      std::size_t n = 0;
      while (n < rest.size() && (std::isdigit(static_cast<unsigned char>(rest[n])) || rest[n] == '-' || rest[n] == '.')) ++n;
      std::string number = rest.substr(0, n);
      double want = std::stod(number);
      auto* d = find(name);
      ASSERT_NE(d, nullptr) << "signal " << name << " not decoded";
      EXPECT_NEAR(d->physical, want, tolerance_of(number)) << name;
      if (n < rest.size() && rest[n] == '(') {
        std::string label = rest.substr(n + 1, rest.find(')', n) - n - 1);
        const auto* sig = &signal_of(*m, *d);
        auto* c = sig->choice(d->raw_signed());
        ASSERT_NE(c, nullptr) << name;
        EXPECT_EQ(*c, label);
      }
      ++checked_values;
    }
  }
  EXPECT_EQ(rows, 13);
  EXPECT_GE(checked_values, 20);
}

TEST(Golden, Ft86LogMatchesCanmatrixStatistics) {
  Database db = load_dbc(kShared + "/data/can/ft86_motec/sample_can_spec.dbc");
  std::ifstream in(kShared + "/data/can/ft86_motec/can_sample.log");
  ASSERT_TRUE(in);
  struct Stat {
    long count = 0;
    double min = 1e300, max = -1e300, first = 0, last = 0;
    std::int64_t first_ts = 0, last_ts = 0;
  };
  std::map<std::string, Stat> stats;
  std::string line, why;
  std::vector<DecodedSignal> out;
  long bad = 0;
  while (std::getline(in, line)) {
    auto r = parse_candump_line(line, &why);
    if (!r) {
      ++bad;
      continue;
    }
    const DbcMessage* m = db.find(r->frame.id, r->frame.extended);
    if (!m) continue;
    decode(*m, std::span(r->frame.data.data(), r->frame.len), out);
    for (auto& d : out) {
      auto& s = stats[m->name + "." + signal_of(*m, d).name];
      if (s.count++ == 0) {
        s.first = d.physical;
        s.first_ts = r->frame.timestamp_ns;
      }
      s.last = d.physical;
      s.last_ts = r->frame.timestamp_ns;
      s.min = std::min(s.min, d.physical);
      s.max = std::max(s.max, d.physical);
    }
  }
  EXPECT_EQ(bad, 0);
  std::ifstream ex(kShared + "/data/can/ft86_motec/expected_canmatrix_stats.csv");
  ASSERT_TRUE(ex);
  std::getline(ex, line);
  int rows = 0;
  while (std::getline(ex, line)) {
    auto c = split_csv(line);
    ASSERT_EQ(c.size(), 9u);
    SCOPED_TRACE(line);
    auto it = stats.find(c[0] + "." + c[1]);
    ASSERT_NE(it, stats.end());
    const Stat& s = it->second;
    EXPECT_EQ(s.count, std::stol(c[2]));
    EXPECT_NEAR(s.min, std::stod(c[3]), tolerance_of(c[3]));
    EXPECT_NEAR(s.max, std::stod(c[4]), tolerance_of(c[4]));
    EXPECT_NEAR(s.first, std::stod(c[5]), tolerance_of(c[5]));
    EXPECT_NEAR(s.last, std::stod(c[6]), tolerance_of(c[6]));
    // Timestamps are microseconds in the log; the CSV prints them to 6 decimals.
    EXPECT_NEAR(static_cast<double>(s.first_ts) / 1e9, std::stod(c[7]), 1.5e-6);
    EXPECT_NEAR(static_cast<double>(s.last_ts) / 1e9, std::stod(c[8]), 1.5e-6);
    ++rows;
  }
  EXPECT_EQ(rows, 20);
}
