// codec_bench's main: Google Benchmark's, plus a closing table of ratios measured in this run
// (nlohmann's CPU time over ours: how many times faster we are; ours over simdjson's: how far
// from the decode speed limit). With --benchmark_repetitions the medians are compared.
// Console output only: --benchmark_format=json or csv prints what Google Benchmark prints.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(bool color) : ConsoleReporter(color ? OO_Defaults : OO_Tabular) {}
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      const std::string name = run.run_name.function_name;
      if (run.run_type == Run::RT_Aggregate) {
        if (run.aggregate_name == "median") medians_[name] = run.GetAdjustedCPUTime();
      } else {
        last_[name] = run.GetAdjustedCPUTime();
      }
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    std::printf("\nRatios, CPU time, this run%s:\n",
                medians_.empty() ? "" : " (medians of the repetitions)");
    for (const char* message : {"ControlDecodeEncode", "ResponseDecodeEncode"}) {
      ratio(message, "Nlohmann", "Ours", "x faster than nlohmann");
    }
    for (const char* message : {"ControlDecode", "ResponseDecode"}) {
      ratio(message, "Nlohmann", "Ours", "x faster than nlohmann");
      ratio(message, "Ours", "Simdjson", "x the time of simdjson On-Demand (the decode speed limit)");
    }
  }

 private:
  // time(BM_<message>_<numerator>) / time(BM_<message>_<denominator>), when both ran.
  void ratio(const std::string& message, const std::string& numerator,
             const std::string& denominator, const char* meaning) const {
    const double* top = find("BM_" + message + "_" + numerator);
    const double* bottom = find("BM_" + message + "_" + denominator);
    if (top == nullptr || bottom == nullptr || *bottom <= 0.0) return;
    std::printf("  %-22s %7.1f %s\n", message.c_str(), *top / *bottom, meaning);
  }
  const double* find(const std::string& name) const {
    for (const auto* times : {&medians_, &last_}) {
      const auto found = times->find(name);
      if (found != times->end()) return &found->second;
    }
    return nullptr;
  }

  std::map<std::string, double> medians_;
  std::map<std::string, double> last_;
};

bool console_output(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--benchmark_format=", 19) == 0) {
      return std::strcmp(argv[i] + 19, "console") == 0;
    }
  }
  return true;
}

// Colours only on a terminal, and never after --benchmark_color=false (or no).
bool colour_output(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--benchmark_color=false") == 0 || std::strcmp(argv[i], "--benchmark_color=no") == 0) {
      return false;
    }
  }
  return isatty(STDOUT_FILENO) != 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool console = console_output(argc, argv);   // before Initialize takes the flags out
  const bool colour = colour_output(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (console) {
    RatioReporter reporter(colour);
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
