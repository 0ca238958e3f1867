// Suite results as text: one line per set-up, Markdown tables for docs/accuracy.md, or JSON.
#pragma once

#include <string>

#include "iilfm/eval/suite.hpp"

namespace iilfm::eval {

// "<set-up> [plane]: found 5/5, ... " in millimetres and degrees.
std::string summary_line(const SetupResult& result);

// One table per group (paper table), rows set-up x lifting method, and a line saying how the
// numbers were made.
std::string to_markdown(const SuiteResult& suite);

// One table of every set-up's claimed uncertainty (covariance) against its observed error.
std::string uncertainty_markdown(const SuiteResult& suite);

// Every case and every summary; 2-space indented.
std::string to_json(const SuiteResult& suite);

}  // namespace iilfm::eval
