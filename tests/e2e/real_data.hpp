// Test helper: the real recorded scans beside the checkout (../shared/data/real, see SOURCES.md).
#pragma once

#include <filesystem>
#include <vector>

namespace iilfm::testing {

// The folder of real data; tests skip when it is not there.
std::filesystem::path real_data_dir();

// Every Pandar64 frame of the two OpenCalib folders, sorted; empty when the data is missing.
std::vector<std::filesystem::path> pandar64_scans();

}  // namespace iilfm::testing
