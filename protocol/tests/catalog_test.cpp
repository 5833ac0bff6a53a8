// The catalog is the contract between the two builds: ids are fixed and its hash is stable.
#include <gtest/gtest.h>

#include <set>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol {
namespace {

TEST(Catalog, IdsUniqueSortedAndFindable) {
  std::set<SignalId> ids;
  std::set<std::string_view> names;
  for (const auto& s : catalog()) {
    EXPECT_TRUE(ids.insert(s.id).second) << s.id;
    EXPECT_TRUE(names.insert(s.name).second) << s.name;
    EXPECT_LE(s.min, s.max) << s.name;
    EXPECT_EQ(find_signal(s.id), &s);
    EXPECT_EQ(find_signal(s.name), &s);
  }
  EXPECT_EQ(find_signal(SignalId{999}), nullptr);
  EXPECT_EQ(find_signal("Vehicle.NoSuchThing"), nullptr);
}

TEST(Catalog, WellKnownIdsKeepTheirVssNames) {
  EXPECT_EQ(find_signal(sig::kSpeed)->name, "Vehicle.Speed");
  EXPECT_EQ(find_signal(sig::kEngineSpeed)->name, "Vehicle.Powertrain.CombustionEngine.Speed");
  EXPECT_EQ(find_signal(sig::kFuelLevel)->name, "Vehicle.Powertrain.FuelSystem.RelativeLevel");
}

TEST(Catalog, HashIsDeterministicAndNonTrivial) {
  EXPECT_EQ(catalog_hash(), catalog_hash());
  EXPECT_NE(catalog_hash(), 0xcbf29ce484222325ULL);  // not the empty FNV basis
}

TEST(Catalog, StatusNamesRoundTrip) {
  for (auto s : {SignalStatus::Valid, SignalStatus::TimedOut, SignalStatus::Invalid, SignalStatus::NotAvailable}) {
    EXPECT_EQ(status_from_string(to_string(s)), s);
  }
  EXPECT_FALSE(status_from_string("bogus"));
}

}  // namespace
}  // namespace meter::protocol
