// The detector's view of the shared dictionary table (include/iilfm/aruco_dictionaries.hpp).
#pragma once

#include "iilfm/aruco_dictionaries.hpp"

namespace iilfm::detail {

using iilfm::aruco_dictionaries;
using iilfm::ArucoDictionaryEntry;
using iilfm::find_aruco_dictionary;

}  // namespace iilfm::detail
