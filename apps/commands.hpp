// Each subcommand of the `iilfm` program lives in its own file and registers itself here.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace iilfm::cli {

// A registered subcommand runs through the returned callback after parsing; the callback returns
// the process exit status. InputError thrown inside is turned into "iilfm: <message>" and exit 2.
using Runner = std::function<int()>;

Runner register_detect_command(CLI::App& app);
Runner register_sim_command(CLI::App& app);
Runner register_sensors_command(CLI::App& app);
Runner register_eval_command(CLI::App& app);
Runner register_bag_command(CLI::App& app);
Runner register_marker_command(CLI::App& app);

}  // namespace iilfm::cli
