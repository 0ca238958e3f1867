// Test recordings made by tests/tools/make_bags.py with Debian's real ROS 1 writer (python3-rosbag)
// and, for ROS 2, by the same script following the rosbag2 sqlite3 schema and CDR. Generated once
// per test program into a temporary folder; expected.json holds what the script wrote.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "io_test_support.hpp"

namespace iilfm::io::testing {

inline const char* kSystemPython = "/usr/bin/python3";

inline std::string make_bags_script() {
  return std::string(IILFM_SOURCE_DIR) + "/tests/tools/make_bags.py";
}

// Empty when Debian's ROS 1 python modules are missing (scripts/setup.sh installs them).
inline std::string ros_python_missing() {
  static const std::string missing = []() -> std::string {
    const std::string probe =
        std::string(kSystemPython) + " -c 'import rosbag, genpy, sensor_msgs.msg' >/dev/null 2>&1";
    if (std::system(probe.c_str()) != 0)
      return "needs /usr/bin/python3 with python3-rosbag, python3-genpy and python3-sensor-msgs "
             "(scripts/setup.sh)";
    return std::string();
  }();
  return missing;
}

// The folder with the generated recordings; generated on first use. Fails the test when the
// script fails.
inline const std::string& test_bags_dir() {
  static TempDir dir;
  static bool made = false;
  if (!made) {
    const std::string folder = dir.file(".");
    for (const char* what : {"ros1", "ros2"}) {
      const std::string command =
          std::string(kSystemPython) + " " + make_bags_script() + " " + what + " '" + folder + "'";
      if (std::system(command.c_str()) != 0)
        throw std::runtime_error("test data script failed: " + command);
    }
    made = true;
  }
  static const std::string path = dir.file(".");
  return path;
}

inline nlohmann::json load_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace iilfm::io::testing

// In a test body: skips with the reason when the ROS python modules are absent.
#define SKIP_WITHOUT_ROS_PYTHON()                              \
  do {                                                         \
    const std::string missing = testing::ros_python_missing(); \
    if (!missing.empty()) GTEST_SKIP() << missing;             \
  } while (0)
