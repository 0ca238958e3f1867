#include "cli_run.hpp"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "support/scratch_dir.hpp"

namespace iilfm::testing {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path cli_temp_dir() { return iilfm::testing::process_scratch_dir(); }

int shell(const std::string& command) {
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
}

CliRun run_cli(const std::string& args) {
  const fs::path out = cli_temp_dir() / "stdout.txt", err = cli_temp_dir() / "stderr.txt";
  CliRun r;
  r.status = shell(std::string(IILFM_CLI_PATH) + " " + args + " >" + out.string() + " 2>" +
                   err.string() + " </dev/null");
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace iilfm::testing
