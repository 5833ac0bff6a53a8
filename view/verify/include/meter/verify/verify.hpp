// meter-verify: a test engineer's check of a run. Given a scene package (with its integrity
// table, meter/bridge/integrity.hpp) and a run folder (frames.csv + the PNGs meter-view dumped,
// live or offline), every dumped frame's safety regions are judged with the engine's pure checks
// (meter/engine/integrity_check.hpp) against what the frame's values say they must show:
// telltales lit exactly when the bindings light them, needle angles within their bound, readout
// texts equal to their value's formatted text (compared with the engine's own rendering of that
// text in the frame's state). Docs: docs/integrity.md.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/engine/integrity_check.hpp"

namespace meter::verify {

struct VerifyOptions {
  std::string package;           // .msp written by meter-convert
  std::string run_dir;           // holds frames.csv and the PNGs it names
  std::string junit;             // JUnit XML to write; empty = none
  std::string backend = "egl";   // readouts' reference renders: egl | osmesa
  int msaa = 4;                  // the run's --msaa (the reference is rendered alike)
};

struct CheckResult {
  std::uint64_t frame = 0;
  std::string png;
  std::string region;
  bridge::SafetyKind kind = bridge::SafetyKind::Telltale;
  bool checked = false;          // false: nothing drove the region yet (JUnit "skipped")
  engine::Verdict verdict;
};

struct VerifyReport {
  std::string package, run_dir;
  std::size_t frames = 0;
  std::vector<CheckResult> checks;  // frame by frame, regions in table order
  std::size_t failures() const;
};

// Throws VerifyError (or the engine's SceneError) naming the bad input: a missing or unreadable
// package, a package without an integrity table, a missing frames.csv or PNG, a frame of another
// size than the table's, a frames.csv without the columns of the package's bindings.
VerifyReport verify_run(const VerifyOptions& options);

// One line per region (checks, failures, largest difference), then one per failure.
std::string summary_table(const VerifyReport& report);
// JUnit XML: one testsuite per run, one testcase per frame and region (classname = the PNG).
std::string junit_xml(const VerifyReport& report);

// What meter-verify does: 0 every check passed, 1 a mismatch or a bad input (named on `err`).
int run_verify_tool(const VerifyOptions& options, std::ostream& out, std::ostream& err);

}  // namespace meter::verify
