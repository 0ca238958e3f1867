// The HTML report's viewer script (web/src/report.js with three.js, minified), generated into the
// build directory by cmake/report_viewer.cmake; empty when built with -DIILFM_HTML_REPORT=OFF.
#pragma once

#include <string_view>

namespace iilfm::detail {

std::string_view report_viewer_script();

}  // namespace iilfm::detail
