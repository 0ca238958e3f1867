// The `iilfm` command-line program: parses the subcommand and hands over to it.
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "iilfm/error.hpp"
#include "opencv_threads.hpp"

int main(int argc, char** argv) {
  CLI::App app{"iilfm: LiDAR fiducial markers through intensity images"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "iilfm 0.1.0");

  std::vector<std::pair<CLI::App*, iilfm::cli::Runner>> commands;
  auto add = [&](iilfm::cli::Runner (*registrar)(CLI::App&)) {
    const std::size_t before = app.get_subcommands({}).size();
    iilfm::cli::Runner run = registrar(app);
    commands.emplace_back(app.get_subcommands({})[before], std::move(run));
  };
  add(iilfm::cli::register_detect_command);
  add(iilfm::cli::register_sim_command);
  add(iilfm::cli::register_sensors_command);
  add(iilfm::cli::register_eval_command);
  add(iilfm::cli::register_bag_command);
  add(iilfm::cli::register_bench_command);
  add(iilfm::cli::register_marker_command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "iilfm: " << e.what() << " (see iilfm --help)\n";
    return 2;
  }

  iilfm::cli::use_opencv_threads(1);  // commands with --threads raise it
  try {
    for (auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
  } catch (const iilfm::InputError& e) {
    std::cerr << "iilfm: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "iilfm: internal error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
