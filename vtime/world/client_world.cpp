// External client processes in a virtual-time World (client_world.hpp).
#include "vtime/client_world.hpp"

#include "ocp/virtual_executor.hpp"
#include "world/world.hpp"

namespace ocp::vtime {

namespace {

// Launches one client process on `port` under the controller's shim, announced to it.
LaunchedClient launch(Controller& controller, const std::string& name, const std::vector<std::string>& command,
                      std::uint16_t port, const VirtualClientOptions& clients) {
  LaunchedClient client{name, clients.log_path ? clients.log_path(name) : "", nullptr};
  auto launched = sim_app::ClientProcess::launch(command, port, client.log_path, controller.environment());
  if (!launched) throw scenario::HarnessError("cannot start the client: " + launched.error().message());
  client.process = std::move(*launched);
  sim_app::ClientProcess* process = client.process.get();
  const std::string what = name == operator_name ? "the operator client" : "the client (" + name + ")";
  controller.expect_process(process->pid(), what, [process] { return process->running(); });
  return client;
}

std::vector<std::string> command_of(const std::string& line, const std::vector<std::string>& argv) {
  return argv.empty() ? std::vector<std::string>{"/bin/sh", "-c", line} : argv;
}

}  // namespace

VirtualClientRun run_with_virtual_clients(const scenario::Scenario& scenario, const scenario::RunOptions& options,
                                          const VirtualClientOptions& clients) {
  VirtualClientRun run;
  std::unique_ptr<Controller> controller;   // destroyed before the clients: their shims let go first
  try {
    run.result = scenario::run_scenario_driven(scenario, options, [&](World& world, VirtualExecutor& executor, SimTime end) {
      controller = std::make_unique<Controller>(executor, clients.controller);
      for (const VehicleSpec& spec : scenario.world.vehicles) {
        if (spec.in_process_client) continue;
        const int listener = controller->listen(0, [&world, name = spec.name](std::shared_ptr<ByteStream> stream) {
          world.accept_vehicle_connection(name, std::move(stream));
        });
        world.set_vehicle_listener(spec.name, [&controller, listener](Micros down) { controller->close_listener_for(listener, down); });
        run.clients.push_back(launch(*controller, spec.name, command_of(clients.command, clients.argv),
                                     controller->port(listener), clients));
      }
      if (!clients.operator_command.empty() || !clients.operator_argv.empty()) {
        const int listener = controller->listen(0, [&world](std::shared_ptr<ByteStream> stream) {
          world.player().accept_client_connection(std::move(stream));
        });
        run.operator_client = launch(*controller, operator_name, command_of(clients.operator_command, clients.operator_argv),
                                     controller->port(listener), clients);
      }
      return controller->run_until(end, options.interrupted);
    });
  } catch (...) {
    controller.reset();
    throw;
  }
  if (controller) run.stats = controller->stats();
  for (LaunchedClient& client : run.clients) client.running_at_end = client.process->running();
  if (run.operator_client) run.operator_client->running_at_end = run.operator_client->process->running();
  controller.reset();
  return run;
}

}  // namespace ocp::vtime
