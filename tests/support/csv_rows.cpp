#include "csv_rows.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

namespace meter::testing {

namespace fs = std::filesystem;

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    if (cells.size() < header.size()) continue;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

void wait_for_first_dump(const fs::path& frames_csv, ChildProcess& view) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(frames_csv) || read_csv(frames_csv).empty()) {
    ASSERT_TRUE(view.running()) << "meter-view ended before its first frame:\n" << view.log();
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "meter-view dumped no frame in 30 s:\n" << view.log();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace meter::testing
