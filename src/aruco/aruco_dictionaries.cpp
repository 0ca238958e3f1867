// OpenCV's predefined dictionaries by their enumerator names.
#include "iilfm/aruco_dictionaries.hpp"

namespace iilfm {

const std::vector<ArucoDictionaryEntry>& aruco_dictionaries() {
  using namespace cv::aruco;
  static const std::vector<ArucoDictionaryEntry> dictionaries = {
      {"DICT_4X4_50", DICT_4X4_50},
      {"DICT_4X4_100", DICT_4X4_100},
      {"DICT_4X4_250", DICT_4X4_250},
      {"DICT_4X4_1000", DICT_4X4_1000},
      {"DICT_5X5_50", DICT_5X5_50},
      {"DICT_5X5_100", DICT_5X5_100},
      {"DICT_5X5_250", DICT_5X5_250},
      {"DICT_5X5_1000", DICT_5X5_1000},
      {"DICT_6X6_50", DICT_6X6_50},
      {"DICT_6X6_100", DICT_6X6_100},
      {"DICT_6X6_250", DICT_6X6_250},
      {"DICT_6X6_1000", DICT_6X6_1000},
      {"DICT_7X7_50", DICT_7X7_50},
      {"DICT_7X7_100", DICT_7X7_100},
      {"DICT_7X7_250", DICT_7X7_250},
      {"DICT_7X7_1000", DICT_7X7_1000},
      {"DICT_ARUCO_ORIGINAL", DICT_ARUCO_ORIGINAL},
      {"DICT_APRILTAG_16h5", DICT_APRILTAG_16h5},
      {"DICT_APRILTAG_25h9", DICT_APRILTAG_25h9},
      {"DICT_APRILTAG_36h10", DICT_APRILTAG_36h10},
      {"DICT_APRILTAG_36h11", DICT_APRILTAG_36h11},
  };
  return dictionaries;
}

const ArucoDictionaryEntry* find_aruco_dictionary(const std::string& name) {
  for (const ArucoDictionaryEntry& entry : aruco_dictionaries())
    if (name == entry.name) return &entry;
  return nullptr;
}

}  // namespace iilfm
