// OpenCV's predefined ArUco dictionaries by name ("DICT_4X4_50", ...), shared by the detector
// back-end and the simulator's print.
#pragma once

#include <opencv2/aruco/dictionary.hpp>
#include <string>
#include <vector>

namespace iilfm {

struct ArucoDictionaryEntry {
  const char* name;  // OpenCV's enumerator name, e.g. "DICT_4X4_50"
  cv::aruco::PREDEFINED_DICTIONARY_NAME id;
};

// Every predefined dictionary of OpenCV 4.6, in enumerator order.
const std::vector<ArucoDictionaryEntry>& aruco_dictionaries();
const ArucoDictionaryEntry* find_aruco_dictionary(const std::string& name);

}  // namespace iilfm
