// A campaign's efficiency figures (efficiency.hpp).
#include "campaign/efficiency.hpp"

#include <cstdio>

namespace ocp::campaign {

Efficiency efficiency_of(const CampaignRun& run) {
  Efficiency efficiency;
  efficiency.worlds = run.outcomes.size();
  efficiency.workers = run.workers;
  efficiency.wall_seconds = run.wall_seconds;
  for (const WorldOutcome& outcome : run.outcomes) {
    efficiency.simulated_seconds += static_cast<double>(outcome.duration.count()) / 1e6;
  }
  efficiency.process_cpu_seconds = run.process_cpu_seconds;
  efficiency.children_cpu_seconds = run.children_cpu_seconds;
  efficiency.world_cpu_seconds = run.cpu_seconds;
  return efficiency;
}

std::string efficiency_text(const Efficiency& e) {
  char text[512];
  std::snprintf(text, sizeof text,
                "%zu worlds on %d worker%s in %.2f s wall: %.1f worlds/s, %.2f worlds/s per worker\n"
                "%.2f s CPU (process %.2f s, client processes %.2f s): %.0f simulated s per CPU s, "
                "%.1f ms CPU per world (%.1f ms inside the worlds)\n",
                e.worlds, e.workers, e.workers == 1 ? "" : "s", e.wall_seconds, e.worlds_per_second(),
                e.worlds_per_second_per_worker(), e.cpu_seconds(), e.process_cpu_seconds, e.children_cpu_seconds,
                e.simulated_per_cpu_second(), e.cpu_ms_per_world(), e.world_cpu_ms_per_world());
  return text;
}

std::string efficiency_json(const Efficiency& e) {
  struct Field {
    const char* name;
    double value;
    int decimals;
  };
  const Field fields[] = {
      {"worlds", static_cast<double>(e.worlds), 0},
      {"workers", static_cast<double>(e.workers), 0},
      {"wall_seconds", e.wall_seconds, 6},
      {"simulated_seconds", e.simulated_seconds, 6},
      {"cpu_seconds", e.cpu_seconds(), 6},
      {"process_cpu_seconds", e.process_cpu_seconds, 6},
      {"children_cpu_seconds", e.children_cpu_seconds, 6},
      {"world_cpu_seconds", e.world_cpu_seconds, 6},
      {"worlds_per_second", e.worlds_per_second(), 6},
      {"worlds_per_second_per_worker", e.worlds_per_second_per_worker(), 6},
      {"simulated_seconds_per_cpu_second", e.simulated_per_cpu_second(), 6},
      {"cpu_ms_per_world", e.cpu_ms_per_world(), 6},
  };
  std::string json = "{";
  for (const Field& field : fields) {
    char line[128];
    std::snprintf(line, sizeof line, "%s\n  \"%s\": %.*f", json.size() > 1 ? "," : "", field.name, field.decimals,
                  field.value);
    json += line;
  }
  return json + "\n}\n";
}

}  // namespace ocp::campaign
