// meter-verify's outputs: the summary table for people and JUnit XML for CI.
#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include "meter/verify/verify.hpp"

namespace meter::verify {
namespace {

std::string xml_escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters other than tab / newline are not allowed in XML 1.0.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') out += ' ';
        else out += c;
    }
  }
  return out;
}

std::string failure_line(const CheckResult& c) {
  char diff[32];
  std::snprintf(diff, sizeof diff, "%.3f", c.verdict.difference);
  return "frame " + std::to_string(c.frame) + " (" + c.png + "), " + to_string(c.kind) + " " + c.region + ": expected " +
         c.verdict.expected + ", seen " + c.verdict.seen + ", difference " + diff;
}

}  // namespace

std::string summary_table(const VerifyReport& r) {
  struct Row {
    bridge::SafetyKind kind{};
    std::size_t checks = 0, failures = 0, skipped = 0;
    double worst = 0;
  };
  std::vector<std::string> order;
  std::map<std::string, Row> rows;
  for (const auto& c : r.checks) {
    auto [it, fresh] = rows.try_emplace(c.region);
    if (fresh) order.push_back(c.region);
    Row& row = it->second;
    row.kind = c.kind;
    if (!c.checked) {
      ++row.skipped;
      continue;
    }
    ++row.checks;
    row.failures += !c.verdict.ok;
    row.worst = std::max(row.worst, c.verdict.difference);
  }
  std::ostringstream os;
  char buf[256];
  os << "meter-verify: " << r.package << " against " << r.run_dir << ": " << r.frames << " frames, "
     << r.checks.size() << " checks, " << r.failures() << " failed\n";
  std::snprintf(buf, sizeof buf, "  %-8s %-22s %7s %8s %7s %12s\n", "kind", "region", "checks", "failures", "skipped",
                "largest diff");
  os << buf;
  for (const auto& name : order) {
    const Row& row = rows[name];
    std::snprintf(buf, sizeof buf, "  %-8s %-22s %7zu %8zu %7zu %12.3f\n", to_string(row.kind), name.c_str(), row.checks,
                  row.failures, row.skipped, row.worst);
    os << buf;
  }
  for (const auto& c : r.checks)
    if (c.checked && !c.verdict.ok) os << "FAIL " << failure_line(c) << "\n";
  return os.str();
}

std::string junit_xml(const VerifyReport& r) {
  std::size_t skipped = 0;
  for (const auto& c : r.checks) skipped += !c.checked;
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  os << "<testsuites name=\"meter-verify\" tests=\"" << r.checks.size() << "\" failures=\"" << r.failures() << "\">\n";
  os << "  <testsuite name=\"" << xml_escaped(r.run_dir) << "\" tests=\"" << r.checks.size() << "\" failures=\""
     << r.failures() << "\" errors=\"0\" skipped=\"" << skipped << "\">\n";
  os << "    <properties><property name=\"package\" value=\"" << xml_escaped(r.package) << "\"/></properties>\n";
  for (const auto& c : r.checks) {
    os << "    <testcase classname=\"" << xml_escaped(c.png) << "\" name=\"" << to_string(c.kind) << " "
       << xml_escaped(c.region) << "\" time=\"0\"";
    if (!c.checked) {
      os << "><skipped message=\"nothing drives the region yet\"/></testcase>\n";
    } else if (!c.verdict.ok) {
      os << "><failure message=\"" << xml_escaped(failure_line(c)) << "\" type=\"integrity\">expected "
         << xml_escaped(c.verdict.expected) << "\nseen " << xml_escaped(c.verdict.seen) << "\ndifference "
         << c.verdict.difference << "</failure></testcase>\n";
    } else {
      os << "/>\n";
    }
  }
  os << "  </testsuite>\n</testsuites>\n";
  return os.str();
}

}  // namespace meter::verify
