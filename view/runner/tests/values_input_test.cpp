// --set and the values CSV: the state they give and the errors they raise (file:line, field).
#include "meter/runner/values_input.hpp"

#include <cmath>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/protocol/catalog.hpp"
#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using protocol::SignalState;
using protocol::SignalStatus;
using protocol::SignalTable;
using ::testing::HasSubstr;
constexpr protocol::SignalId kSpeed = protocol::sig::kSpeed;
constexpr protocol::SignalId kRpm = protocol::sig::kEngineSpeed;
constexpr protocol::SignalId kGear = protocol::sig::kCurrentGear;

// How many signals the input gave a state other than the table's resting one.
std::size_t set_count(const SignalTable& v) {
  std::size_t n = 0;
  for (const auto& s : v.states()) n += s == SignalState{} ? 0 : 1;
  return n;
}
bool untouched(const SignalTable& v, protocol::SignalId id) { return v.get(id) == SignalState{}; }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ViewError& e) {
    return e.what();
  }
  return "(no error)";
}

SignalTable csv_at(const std::string& text, double t) {
  std::istringstream in(text);
  SignalTable v;
  read_values_csv(in, "drive.csv", t, v);
  return v;
}

std::string csv_error(const std::string& text, double t = 1e300) {
  return error_of([&] { csv_at(text, t); });
}

TEST(ParseSet, NumberIsValidUnlessAStatusIsGiven) {
  SignalTable v;
  parse_set("Vehicle.Speed=100.5", v, "--set");
  parse_set("Vehicle.Powertrain.CombustionEngine.Speed=3000@timed-out", v, "--set");
  parse_set("Vehicle.Powertrain.Transmission.CurrentGear=-1@not-available", v, "--set");
  ASSERT_EQ(set_count(v), 3u);
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 100.5);
  EXPECT_EQ(v.get(kSpeed).status, SignalStatus::Valid);
  EXPECT_DOUBLE_EQ(v.get(kRpm).value, 3000.0);
  EXPECT_EQ(v.get(kRpm).status, SignalStatus::TimedOut);
  EXPECT_DOUBLE_EQ(v.get(kGear).value, -1.0);
  EXPECT_EQ(v.get(kGear).status, SignalStatus::NotAvailable);
}

TEST(ParseSet, ALaterSetReplacesAnEarlierOne) {
  SignalTable v;
  parse_set("Vehicle.Speed=10", v, "--set");
  parse_set("Vehicle.Speed=20@invalid", v, "--set");
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 20.0);
  EXPECT_EQ(v.get(kSpeed).status, SignalStatus::Invalid);
}

TEST(ParseSet, ErrorsNameWhereAndWhat) {
  SignalTable v;
  EXPECT_EQ(error_of([&] { parse_set("Vehicle.Speed", v, "--set"); }),
            "--set: expected NAME=VALUE, got \"Vehicle.Speed\"");
  EXPECT_EQ(error_of([&] { parse_set("=3", v, "--set"); }), "--set: expected NAME=VALUE, got \"=3\"");
  EXPECT_EQ(error_of([&] { parse_set("Vehicle.Sped=3", v, "--set"); }),
            "--set: \"Vehicle.Sped\" is not in the signal catalog");
  EXPECT_EQ(error_of([&] { parse_set("Vehicle.Speed=fast", v, "--set"); }),
            "--set: value \"fast\" for Vehicle.Speed is not a finite number");
  EXPECT_THAT(error_of([&] { parse_set("Vehicle.Speed=3@stale", v, "--set"); }),
              HasSubstr("--set: unknown status \"stale\" (valid, timed-out, invalid, not-available)"));
  EXPECT_EQ(v, SignalTable{}) << "nothing is set by a bad argument";
}

TEST(ParseSet, RejectsNonFiniteAndTrailingGarbage) {
  SignalTable v;
  for (const char* bad : {"nan", "inf", "-inf", "12km/h", "1e999", "", " 5 "}) {
    EXPECT_THAT(error_of([&] { parse_set(std::string("Vehicle.Speed=") + bad, v, "--set"); }),
                HasSubstr("is not a finite number"))
        << bad;
  }
  EXPECT_EQ(v, SignalTable{});
}

TEST(ValuesCsv, StateAtATimeIsEachSignalsLastRowAtOrBeforeIt) {
  const std::string csv =
      "time,signal,value,status\n"
      "0,Vehicle.Speed,0\n"
      "# a comment\n"
      "\n"
      "1.0,Vehicle.Speed,50\r\n"
      "1.5,Vehicle.Powertrain.CombustionEngine.Speed,2000,timed-out\n"
      "2.0,Vehicle.Speed,80\n";
  auto at0 = csv_at(csv, 0.0);
  ASSERT_EQ(set_count(at0), 1u);
  EXPECT_DOUBLE_EQ(at0.get(kSpeed).value, 0.0);

  auto at1 = csv_at(csv, 1.0);
  EXPECT_DOUBLE_EQ(at1.get(kSpeed).value, 50.0) << "a row exactly at the time counts";
  EXPECT_TRUE(untouched(at1, kRpm));

  auto at19 = csv_at(csv, 1.9);
  EXPECT_DOUBLE_EQ(at19.get(kSpeed).value, 50.0);
  EXPECT_DOUBLE_EQ(at19.get(kRpm).value, 2000.0);
  EXPECT_EQ(at19.get(kRpm).status, SignalStatus::TimedOut);

  auto end = csv_at(csv, 1e300);
  EXPECT_DOUBLE_EQ(end.get(kSpeed).value, 80.0);
  EXPECT_EQ(end.get(kSpeed).status, SignalStatus::Valid);
}

TEST(ValuesCsv, RowsNeedNotBeSortedByTime) {
  const auto v = csv_at("2,Vehicle.Speed,80\n1,Vehicle.Speed,50\n3,Vehicle.Speed,99\n", 2.5);
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 80.0) << "the latest time at or before 2.5 s wins, not the last line";
}

TEST(ValuesCsv, RowsAfterTheTimeAreNotChecked) {
  const auto v = csv_at("1,Vehicle.Speed,50\n5,Nobody,x\n", 2.0);
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 50.0);
}

TEST(ValuesCsv, ABadRowNamesFileLineAndField) {
  EXPECT_EQ(csv_error("time,signal,value\n0,Vehicle.Speed,1\nsoon,Vehicle.Speed,2\n"),
            "drive.csv:3: first column must be a time in seconds, got \"soon\"");
  EXPECT_EQ(csv_error("0,Vehicle.Speed\n"), "drive.csv:1: expected time,signal,value[,status]");
  EXPECT_EQ(csv_error("0,Vehicle.Speed,1,valid,extra\n"), "drive.csv:1: expected time,signal,value[,status]");
  EXPECT_EQ(csv_error("0,Vehicle.Speed,1\n1,Vehicle.Sped,2\n"), "drive.csv:2: \"Vehicle.Sped\" is not in the signal catalog");
  EXPECT_EQ(csv_error("0,Vehicle.Speed,fast\n"), "drive.csv:1: value \"fast\" for Vehicle.Speed is not a finite number");
  EXPECT_THAT(csv_error("0,Vehicle.Speed,1,stale\n"), HasSubstr("drive.csv:1: unknown status \"stale\""));
}

TEST(ValuesCsv, OnlyTheFirstLineMayBeAHeader) {
  EXPECT_EQ(csv_error("# drive\ntime,signal,value\n"), "drive.csv:2: first column must be a time in seconds, got \"time\"");
}

TEST(ValuesCsv, NonFiniteOrGarbageTimesAndValuesAreRejected) {
  EXPECT_EQ(csv_error("nan,Vehicle.Speed,1\n"), "drive.csv:1: first column must be a time in seconds, got \"nan\"");
  EXPECT_EQ(csv_error("inf,Vehicle.Speed,1\n"), "drive.csv:1: first column must be a time in seconds, got \"inf\"");
  EXPECT_EQ(csv_error("0,Vehicle.Speed,1\n1.5s,Vehicle.Speed,1\n"),
            "drive.csv:2: first column must be a time in seconds, got \"1.5s\"");
  EXPECT_THAT(csv_error("0,Vehicle.Speed,nan\n"), HasSubstr("drive.csv:1: value \"nan\""));
  EXPECT_THAT(csv_error("0,Vehicle.Speed,1e400\n"), HasSubstr("is not a finite number"));
}

TEST(ValuesCsv, ABadRowFailsTheWholeLoadEvenAfterGoodRows) {
  // The offline render stops with the error: a state missing a row is never drawn.
  std::istringstream in("0,Vehicle.Speed,10\n1,Vehicle.Speed,oops\n");
  SignalTable v;
  EXPECT_THROW(read_values_csv(in, "drive.csv", 1e300, v), ViewError);
}

TEST(ValuesCsv, FromAFile) {
  const auto dir = testing::scratch_dir();
  testing::write_text(dir / "drive.csv", "0,Vehicle.Speed,42\n");
  SignalTable v;
  load_values_csv((dir / "drive.csv").string(), 1.0, v);
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 42.0);
  const std::string missing = (dir / "missing.csv").string();
  EXPECT_EQ(error_of([&] { load_values_csv(missing, 1.0, v); }), missing + ": cannot open values CSV");
}

TEST(ParseSet, SetsTheNamedSignalOnly) {
  SignalTable v;
  parse_set("Vehicle.Speed=7", v, "--set");
  EXPECT_DOUBLE_EQ(v.get(kSpeed).value, 7.0);
  EXPECT_EQ(v.get(kRpm).status, SignalStatus::NotAvailable) << "a signal never named is not available";
  EXPECT_EQ(set_count(v), 1u);
}

TEST(ParseSet, ReplacesTheWholeStateNotOnlyTheValue) {
  // The table keeps a text across value-only updates; --set gives a signal its whole state.
  SignalTable v;
  v.set_text(kSpeed, "left over", SignalStatus::Valid);
  parse_set("Vehicle.Speed=5@invalid", v, "--set");
  EXPECT_EQ(v.get(kSpeed), (SignalState{5.0, SignalStatus::Invalid, ""}));
}

}  // namespace
}  // namespace meter::runner
