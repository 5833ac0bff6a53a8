// SignalTable: one SignalState per catalog entry, O(1) lookup by id, exact change detection and
// the version stamps a consumer uses to find what changed since it last looked.
#include "meter/protocol/signal_table.hpp"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

namespace meter::protocol {
namespace {

// An id the catalog does not hold (ids are never reused, and none is this large).
constexpr SignalId kUnknown = 60000;

TEST(SignalTable, StartsWithEveryCatalogSignalNotAvailable) {
  const SignalTable table;
  ASSERT_EQ(table.size(), catalog().size());
  ASSERT_EQ(table.states().size(), catalog().size());
  EXPECT_EQ(table.version(), 0U);
  for (const auto& info : catalog()) {
    const SignalState& s = table.get(info.id);
    EXPECT_EQ(s.value, 0.0);
    EXPECT_EQ(s.status, SignalStatus::NotAvailable);
    EXPECT_TRUE(s.text.empty());
    EXPECT_EQ(table.changed_at(info.id), 0U);
  }
}

TEST(SignalTable, IndexFollowsTheCatalogOrder) {
  const SignalTable table;
  for (std::size_t i = 0; i < catalog().size(); ++i) {
    const SignalId id = catalog()[i].id;
    ASSERT_EQ(table.index_of(id), i);
    EXPECT_EQ(table.find(id), &table.states()[i]);
    EXPECT_EQ(&table.get(id), &table.states()[i]);
  }
}

TEST(SignalTable, UnknownIdsAreNullFromFindAndThrowElsewhere) {
  SignalTable table;
  std::set<SignalId> known;
  for (const auto& info : catalog()) known.insert(info.id);
  for (SignalId id : {SignalId{0}, SignalId{19}, kUnknown, SignalId{65535}}) {
    if (known.count(id) != 0) continue;
    EXPECT_FALSE(table.index_of(id).has_value()) << id;
    EXPECT_EQ(table.find(id), nullptr) << id;
    EXPECT_THROW((void)table.get(id), std::out_of_range) << id;
    EXPECT_THROW((void)table.changed_at(id), std::out_of_range) << id;
    EXPECT_THROW(table.set(id, 1.0, SignalStatus::Valid), std::out_of_range) << id;
    EXPECT_THROW(table.set(id, SignalState{}), std::out_of_range) << id;
    EXPECT_THROW(table.set_text(id, "x", SignalStatus::Valid), std::out_of_range) << id;
  }
  EXPECT_EQ(table.version(), 0U);
}

TEST(SignalTable, OnlyObservableChangesCountAndBumpTheVersion) {
  SignalTable table;
  EXPECT_TRUE(table.set(sig::kSpeed, 50.0, SignalStatus::Valid));
  EXPECT_EQ(table.version(), 1U);
  EXPECT_EQ(table.changed_at(sig::kSpeed), 1U);
  EXPECT_EQ(table.changed_at(sig::kEngineSpeed), 0U);

  EXPECT_FALSE(table.set(sig::kSpeed, 50.0, SignalStatus::Valid));  // same again: no change
  EXPECT_EQ(table.version(), 1U);

  EXPECT_TRUE(table.set(sig::kSpeed, 50.0, SignalStatus::TimedOut));  // status alone is a change
  EXPECT_EQ(table.changed_at(sig::kSpeed), 2U);

  // Compared by bits: -0.0 after 0.0 is a change.
  EXPECT_TRUE(table.set(sig::kEngineSpeed, 0.0, SignalStatus::Valid));
  EXPECT_TRUE(table.set(sig::kEngineSpeed, -0.0, SignalStatus::Valid));
  EXPECT_FALSE(table.set(sig::kEngineSpeed, -0.0, SignalStatus::Valid));
  EXPECT_EQ(table.version(), 4U);
  EXPECT_EQ(table.changed_at(sig::kEngineSpeed), 4U);
  EXPECT_EQ(table.get(sig::kSpeed), (SignalState{50.0, SignalStatus::TimedOut, ""}));
}

TEST(SignalTable, EachSetterKeepsWhatItDoesNotName) {
  SignalTable table;
  EXPECT_TRUE(table.set_text(sig::kCurrentGear, "D", SignalStatus::Valid));
  EXPECT_TRUE(table.set(sig::kCurrentGear, 4.0, SignalStatus::Valid));  // value only: text stays
  EXPECT_EQ(table.get(sig::kCurrentGear), (SignalState{4.0, SignalStatus::Valid, "D"}));
  EXPECT_TRUE(table.set_text(sig::kCurrentGear, "R", SignalStatus::Valid));  // text only: value stays
  EXPECT_EQ(table.get(sig::kCurrentGear), (SignalState{4.0, SignalStatus::Valid, "R"}));
  EXPECT_FALSE(table.set_text(sig::kCurrentGear, "R", SignalStatus::Valid));
  // A whole state replaces the text too, clearing it here.
  EXPECT_TRUE(table.set(sig::kCurrentGear, SignalState{4.0, SignalStatus::Valid, ""}));
  EXPECT_EQ(table.get(sig::kCurrentGear).text, "");
  EXPECT_FALSE(table.set(sig::kCurrentGear, SignalState{4.0, SignalStatus::Valid, ""}));
  EXPECT_EQ(table.version(), 4U);
}

TEST(SignalTable, AConsumerFindsWhatChangedSinceItLastLooked) {
  SignalTable table;
  table.set(sig::kSpeed, 10.0, SignalStatus::Valid);
  table.set(sig::kFuelLevel, 40.0, SignalStatus::Valid);
  const std::uint64_t seen = table.version();

  table.set(sig::kSpeed, 11.0, SignalStatus::Valid);
  table.set(sig::kTurnLeft, 1.0, SignalStatus::Valid);
  table.set(sig::kFuelLevel, 40.0, SignalStatus::Valid);  // unchanged: not reported

  std::set<SignalId> changed;
  for (const auto& info : catalog()) {
    if (table.changed_at(info.id) > seen) changed.insert(info.id);
  }
  EXPECT_EQ(changed, (std::set<SignalId>{sig::kSpeed, sig::kTurnLeft}));
}

TEST(SignalTable, EqualityComparesStatesNotHistory) {
  SignalTable a, b;
  EXPECT_EQ(a, b);
  a.set(sig::kSpeed, 1.0, SignalStatus::Valid);
  EXPECT_NE(a, b);
  b.set(sig::kSpeed, 5.0, SignalStatus::Valid);
  b.set(sig::kSpeed, 1.0, SignalStatus::Valid);
  EXPECT_NE(a.version(), b.version());
  EXPECT_EQ(a, b);
  b.set_text(sig::kSpeed, "x", SignalStatus::Valid);
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace meter::protocol
