#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "meter/verify/frames_table.hpp"

namespace fs = std::filesystem;
using namespace meter::verify;

namespace {

fs::path write(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "view" / "verify" / "scratch";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

std::string error_of(const fs::path& p) {
  try {
    read_frames_table(p);
  } catch (const VerifyError& e) {
    return e.what();
  }
  return "";
}

const std::string kHeader = "frame,time_s,png,link_up,drawn,Vehicle.Speed,Vehicle.Speed.status,Vehicle.Speed.failsafe,t.text\n";

}  // namespace

TEST(FramesTable, RowsAndQuotedCellsComeBack) {
  const auto t = read_frames_table(write("ok.csv", kHeader + "30,1.0000,frame_000030.png,1,0,12.5,valid,0,\"say \"\"hi\"\", ok\"\n"));
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].frame, 30u);
  EXPECT_EQ(t.rows[0].line, 2);
  EXPECT_FALSE(t.rows[0].drawn);
  EXPECT_EQ(t.rows[0].cells.at("t.text"), "say \"hi\", ok");
  EXPECT_DOUBLE_EQ(number_cell(t, t.rows[0], "Vehicle.Speed"), 12.5);
}

TEST(FramesTable, BadInputIsNamedByLineAndColumn) {
  EXPECT_NE(error_of(write("none.csv", "")).find("empty file"), std::string::npos);
  EXPECT_NE(error_of("/nonexistent/frames.csv").find("cannot open"), std::string::npos);
  EXPECT_NE(error_of(write("hdr.csv", "a,b\n1,2\n")).find(":1: no column \"frame\""), std::string::npos);
  EXPECT_NE(error_of(write("short.csv", kHeader + "1,0,f.png,1,1,3,valid\n")).find(":2: 7 cells, the header has 9"),
            std::string::npos);
  EXPECT_NE(error_of(write("frame.csv", kHeader + "x,0,f.png,1,1,3,valid,0,\"\"\n")).find(":2: column frame: \"x\""),
            std::string::npos);
  EXPECT_NE(error_of(write("link.csv", kHeader + "1,0,f.png,yes,1,3,valid,0,\"\"\n")).find("column link_up: \"yes\", expected 0 or 1"),
            std::string::npos);
  EXPECT_NE(error_of(write("quote.csv", kHeader + "1,0,f.png,1,1,3,valid,0,\"open\n")).find(":2: unterminated quoted cell"),
            std::string::npos);
  EXPECT_NE(error_of(write("path.csv", kHeader + "1,0,../f.png,1,1,3,valid,0,\"\"\n")).find("column png"), std::string::npos);
  EXPECT_NE(error_of(write("empty.csv", kHeader)).find("no frames"), std::string::npos);
  // A number no frame counter reaches (beyond 2^53 a double no longer holds every integer, and
  // beyond 2^64 it has no frame number at all) is refused, not converted.
  EXPECT_NE(error_of(write("huge.csv", kHeader + "1e300,0,f.png,1,1,3,valid,0,\"\"\n")).find(":2: column frame: \"1e300\""),
            std::string::npos);
  const auto t = read_frames_table(write("nan.csv", kHeader + "1,0,f.png,1,1,nan,valid,0,\"\"\n"));
  EXPECT_THROW(number_cell(t, t.rows[0], "Vehicle.Speed"), VerifyError);  // never a silent NaN
}
