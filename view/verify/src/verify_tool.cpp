#include <fstream>

#include "meter/verify/frames_table.hpp"
#include "meter/verify/verify.hpp"

namespace meter::verify {

int run_verify_tool(const VerifyOptions& o, std::ostream& out, std::ostream& err) {
  try {
    const VerifyReport report = verify_run(o);
    out << summary_table(report);
    if (!o.junit.empty()) {
      std::ofstream x(o.junit, std::ios::trunc);
      if (!x) throw VerifyError(o.junit + ": cannot open for writing");
      x << junit_xml(report);
      if (!x) throw VerifyError(o.junit + ": write failed");
    }
    return report.failures() == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    err << "meter-verify: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::verify
