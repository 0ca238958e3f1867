// Running the built `iilfm` program from the end-to-end tests.
#pragma once

#include <filesystem>
#include <string>

namespace iilfm::testing {

struct CliRun {
  int status = -1;  // exit status, or 128 + signal
  std::string out, err;
};

// The whole file as bytes ("" when it cannot be read).
std::string slurp(const std::filesystem::path& path);

// A scratch folder of this test process, created on first use.
std::filesystem::path cli_temp_dir();

// Runs a shell command; its exit status, or 128 + signal.
int shell(const std::string& command);

// Runs `iilfm ARGS` with stdin from /dev/null, capturing stdout and stderr.
CliRun run_cli(const std::string& args);

}  // namespace iilfm::testing
