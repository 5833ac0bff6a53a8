// ASCII text compared with letter case ignored: letters only, other bytes as they are.
#include <gtest/gtest.h>

#include "meter/protocol/ascii_case.hpp"

namespace meter::protocol {
namespace {

TEST(AsciiCase, LettersMatchInEitherCase) {
  EXPECT_TRUE(equals_ignoring_case("Begin Triggerblock", "BEGIN TRIGGERBLOCK"));
  EXPECT_TRUE(equals_ignoring_case("", ""));
  EXPECT_FALSE(equals_ignoring_case("egl", "eg"));
  EXPECT_FALSE(equals_ignoring_case("egl", "egm"));
}

TEST(AsciiCase, OtherBytesAreComparedAsTheyAre) {
  // '@' + 32 is '`' and '[' - 32 is ';': only A-Z and a-z fold.
  EXPECT_FALSE(equals_ignoring_case("@", "`"));
  EXPECT_FALSE(equals_ignoring_case("[", "{"));
  EXPECT_FALSE(equals_ignoring_case("\xC3\x84", "\xC3\xA4"));  // UTF-8 A and a umlaut: not ASCII letters
  EXPECT_TRUE(equals_ignoring_case("rx_1", "RX_1"));
}

TEST(AsciiCase, LowercaseFoldsOnlyCapitals) {
  EXPECT_EQ(ascii_lowercase("Toyota_Prius-2017.DBC"), "toyota_prius-2017.dbc");
  EXPECT_EQ(ascii_lowercase("@[\xC3\x84"), "@[\xC3\x84");
}

TEST(AsciiCase, PrefixIgnoresCaseAndNeedsTheWholePrefix) {
  EXPECT_TRUE(starts_with_ignoring_case("Toyota_Prius.dbc", "toyota_"));
  EXPECT_TRUE(starts_with_ignoring_case("x", ""));
  EXPECT_FALSE(starts_with_ignoring_case("toy", "toyota_"));
  EXPECT_FALSE(starts_with_ignoring_case("my_toyota.dbc", "toyota_"));
}

}  // namespace
}  // namespace meter::protocol
