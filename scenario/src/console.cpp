// The k6-style verdict lines on the console (reports.hpp).
#include "scenario/reports.hpp"

namespace ocp::scenario {

std::string console_verdicts(const RunReport& report) {
  std::string out;
  for (const Verdict& verdict : report.verdicts) {
    out += verdict.passed ? "  ✓ " : verdict.interrupted ? "  ○ " : "  ✗ ";
    out += verdict.title;
    out += verdict.passed || verdict.interrupted
               ? "\n      " + verdict.actual + "\n"
               : "\n      expected " + verdict.expected + "\n      actual   " + verdict.actual + "\n";
  }
  return out;
}

}  // namespace ocp::scenario
