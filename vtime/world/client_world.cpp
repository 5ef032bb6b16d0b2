// External client processes in a virtual-time World (client_world.hpp).
#include "vtime/client_world.hpp"

#include "ocp/virtual_executor.hpp"
#include "world/world.hpp"

namespace ocp::vtime {

VirtualClientRun run_with_virtual_clients(const scenario::Scenario& scenario, const scenario::RunOptions& options,
                                          const VirtualClientOptions& clients) {
  VirtualClientRun run;
  std::unique_ptr<Controller> controller;   // destroyed before the clients: their shims let go first
  try {
    run.result = scenario::run_scenario_driven(scenario, options, [&](World& world, VirtualExecutor& executor, SimTime end) {
      controller = std::make_unique<Controller>(executor, clients.controller);
      const std::vector<std::string> environment = controller->environment();
      for (const VehicleSpec& spec : scenario.world.vehicles) {
        if (spec.in_process_client) continue;
        const int listener = controller->listen(0, [&world, name = spec.name](std::shared_ptr<ByteStream> stream) {
          world.accept_vehicle_connection(name, std::move(stream));
        });
        world.set_vehicle_listener(spec.name, [&controller, listener](Micros down) { controller->close_listener_for(listener, down); });
        LaunchedClient client{spec.name, clients.log_path ? clients.log_path(spec.name) : "", nullptr};
        const std::vector<std::string> command =
            clients.argv.empty() ? std::vector<std::string>{"/bin/sh", "-c", clients.command} : clients.argv;
        auto launched = sim_app::ClientProcess::launch(command, controller->port(listener), client.log_path, environment);
        if (!launched) throw scenario::HarnessError("cannot start the client: " + launched.error().message());
        client.process = std::move(*launched);
        sim_app::ClientProcess* process = client.process.get();
        controller->expect_process(process->pid(), "the client (" + spec.name + ")", [process] { return process->running(); });
        run.clients.push_back(std::move(client));
      }
      return controller->run_until(end, options.interrupted);
    });
  } catch (...) {
    controller.reset();
    throw;
  }
  if (controller) run.stats = controller->stats();
  controller.reset();
  return run;
}

}  // namespace ocp::vtime
