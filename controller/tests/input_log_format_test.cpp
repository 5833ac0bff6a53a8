#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_format.hpp"

using namespace meter::controller;

namespace {

const std::string kCandump = "(1.000000) can0 100#01\n(1.010000) can0 100#02\n";

std::string message_of(const std::string& path) {
  try {
    read_whole_log(*open_log_source(path));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

struct TempDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("meter-logfmt-" + std::to_string(::getpid()));
  TempDir() { std::filesystem::create_directories(path); }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return (path / name).string();
  }
};

}  // namespace

TEST(LogFormat, TheContentChoosesTheFormatAndTheExtensionOnlyWhenTheContentCannot) {
  EXPECT_EQ(find_log_format("drive.txt", kCandump), &log_formats()[0]);  // by its lines
  EXPECT_EQ(find_log_format("drive", "(bad) line\n" + kCandump), &log_formats()[0]);  // a damaged first line
  EXPECT_EQ(find_log_format("drive.log", "garbage\n"), &log_formats()[0]);  // by .log
  EXPECT_EQ(find_log_format("drive.txt", "garbage\n"), nullptr);
  EXPECT_EQ(find_log_format("drive.txt", ""), nullptr);
  EXPECT_EQ(log_formats()[0].name, "candump");
  EXPECT_EQ(log_format_names(), "candump, asc, blf, trc");
  // The example each format gives in its messages is a line of its own.
  for (const LogFormat& f : log_formats()) EXPECT_TRUE(f.sniff(f.example)) << f.name;
}

TEST(LogFormat, LoadingGoesThroughTheFormatAndNamesTheFileAndLineWhenNoneFits) {
  TempDir dir;
  const ParsedLog log = read_whole_log(*open_log_source(dir.write("drive.rec", kCandump)));
  EXPECT_EQ(log.frames.size(), 2u);
  const ParsedLog bad = read_whole_log(*open_log_source(dir.write("bad.log", "garbage\n" + kCandump)));
  EXPECT_EQ(bad.frames.size(), 2u);
  ASSERT_EQ(bad.bad_lines.size(), 1u);
  EXPECT_EQ(bad.bad_lines[0].line, 1u);

  const std::string path = dir.write("notes.txt", "\n  \nhello world\n");
  const std::string why = message_of(path);
  EXPECT_NE(why.find(path + ": not a CAN log this build reads: line 3 'hello world' starts no known format"),
            std::string::npos) << why;
  EXPECT_NE(why.find("candump, e.g. '(1631416514.717133) can0 0D2#0000FFFF10000000', or any file named *.log"),
            std::string::npos) << why;
  EXPECT_NE(message_of(dir.write("empty.txt", "")).find("empty.txt: not a CAN log this build reads: it is empty"),
            std::string::npos);
  EXPECT_NE(message_of((dir.path / "missing.log").string()).find("missing.log: cannot open the log for reading"),
            std::string::npos);
}

// A file in which not one record gives a frame is refused, whatever command reads it, naming the
// file and its first bad lines; a log with some bad lines still loads with them reported.
TEST(LogFormat, ALogWithoutAUsableFrameIsRefusedNamingItsFirstBadLines) {
  TempDir dir;
  // candump's default output (without -L), named like a candump -L log: no format reads its lines.
  const std::string pcan = dir.write("drive.log",
                                     "  can0  0D2   [8]  00 00 FF FF 10 00 00 00\n"
                                     "  can0  0D3   [7]  00 06 E0 0F 00 00 11\n"
                                     "  can0  0D4   [8]  00 00 00 00 00 00 00 00\n"
                                     "  can0  25C   [8]  25 00 00 00 00 00 00 00\n"
                                     "  can0  140   [8]  00 C2 06 43 00 00 09 A1\n"
                                     "  can0  141   [8]  00 C2 06 43 00 00 09 A1\n");
  // The extension claims it; none of its lines is a candump -L line.
  const std::string why = message_of(pcan);
  EXPECT_NE(why.find(pcan + ": no usable CAN frame"), std::string::npos) << why;
  EXPECT_NE(why.find(pcan + ":1: timestamp: expected"), std::string::npos) << why;
  EXPECT_NE(why.find(pcan + ":3: "), std::string::npos) << why;
  EXPECT_EQ(why.find(pcan + ":6: "), std::string::npos) << why;  // the first three only, then a count
  EXPECT_NE(why.find("and 3 more"), std::string::npos) << why;
  EXPECT_NE(message_of(dir.write("blank.log", "\n\n")).find("blank.log: no usable CAN frame in this candump log: it holds no record"),
            std::string::npos);
}
