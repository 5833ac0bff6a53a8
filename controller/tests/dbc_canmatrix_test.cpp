// The decoder against python3-canmatrix on the same ft86 frames, row by row.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "meter/controller/run/decode_command.hpp"

namespace {
const std::string kSharedDir = METER_SHARED_DIR;
const std::string kFt86Dbc = kSharedDir + "/data/can/ft86_motec/sample_can_spec.dbc";
const std::string kFt86Log = kSharedDir + "/data/can/ft86_motec/can_sample.log";

struct Row {
  std::string ts, message, signal;
  double value;
};

std::vector<Row> parse(std::istream& in, int value_column) {
  std::vector<Row> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) c.push_back(f);
    if (c.size() <= static_cast<std::size_t>(value_column)) continue;
    rows.push_back({c[0], c[1], c[2], std::stod(c[static_cast<std::size_t>(value_column)])});
  }
  return rows;
}
}  // namespace

TEST(Canmatrix, Ft86DecodeMatchesRowByRow) {
  std::string cmd = "/usr/bin/python3 " + std::string(METER_SOURCE_DIR) + "/controller/tests/canmatrix_decode.py " + kFt86Dbc +
                    " " + kFt86Log + " 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string py;
  char buf[65536];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) py.append(buf, n);
  ASSERT_EQ(::pclose(p), 0) << "python3-canmatrix failed";
  std::istringstream pin(py);
  auto ref = parse(pin, 3);
  std::ostringstream out, err;
  ASSERT_EQ(meter::controller::decode_command(kFt86Dbc, kFt86Log, "", out, err), 0) << err.str();
  std::istringstream min(out.str());
  auto ours = parse(min, 4);
  ASSERT_EQ(ref.size(), 91381u);  // the sum of the counts in expected_canmatrix_stats.csv
  ASSERT_EQ(ours.size(), ref.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const auto& a = ours[i];
    const auto& b = ref[i];
    bool same = a.ts == b.ts && a.message == b.message && a.signal == b.signal &&
                std::fabs(a.value - b.value) <= 1e-9 * std::max(1.0, std::fabs(b.value));
    if (!same && ++mismatches <= 5)
      ADD_FAILURE() << "row " << i << ": ours " << a.ts << " " << a.message << "." << a.signal << "=" << a.value
                    << " canmatrix " << b.ts << " " << b.message << "." << b.signal << "=" << b.value;
  }
  EXPECT_EQ(mismatches, 0u);
}
