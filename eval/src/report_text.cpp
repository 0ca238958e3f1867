// Plain-text and Markdown renderings of suite results (millimetres and degrees at the edges).
#include <cstdio>
#include <sstream>

#include "iilfm/eval/report.hpp"

namespace iilfm::eval {
namespace {

std::string format(const char* pattern, double a, double b) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, a, b);
  return buffer;
}

std::string format(const char* pattern, double a) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, a);
  return buffer;
}

// "12.3 (45.6)" in millimetres, or "-" when no case had the figure.
std::string mm(const Stat& s) {
  return s.count ? format("%.1f (%.1f)", s.mean() * 1000, s.worst * 1000) : "-";
}
std::string deg(const Stat& s) { return s.count ? format("%.2f (%.2f)", s.mean(), s.worst) : "-"; }

std::string found(const Summary& s) {
  return std::to_string(s.detected) + "/" + std::to_string(s.visible);
}

std::string seeds_text(const std::vector<std::uint64_t>& seeds) {
  if (seeds.empty()) return "none";
  bool consecutive = true;
  for (std::size_t i = 1; i < seeds.size(); ++i) consecutive &= seeds[i] == seeds[i - 1] + 1;
  if (consecutive && seeds.size() > 1) {
    return std::to_string(seeds.front()) + "-" + std::to_string(seeds.back());
  }
  std::string text;
  for (std::uint64_t s : seeds) text += (text.empty() ? "" : ", ") + std::to_string(s);
  return text;
}

std::string physics_text(const SuiteOptions& o) {
  std::string text = "each sensor's default noise";
  if (o.footprint) text += ", beam footprint on";
  if (o.dark_dropout > 0) text += ", dark dropout " + format("%g", o.dark_dropout);
  if (o.invalid_fraction > 0) text += ", invalid points " + format("%g", o.invalid_fraction);
  return text;
}

}  // namespace

std::string summary_line(const SetupResult& r) {
  const Summary& s = r.summary;
  std::ostringstream out;
  out << r.setup.name << " [" << lift_name(r.lift) << "]: found " << found(s)
      << ", false positives " << s.false_positives << ", wrong ids " << s.wrong_ids
      << ", vertex error mm " << mm(s.corner_error) << ", marker pose mm " << mm(s.marker_position)
      << " deg " << deg(s.marker_rotation_deg) << ", LiDAR pose " << s.poses << "/" << s.cases
      << " mm " << mm(s.position) << " deg " << deg(s.rotation_deg)
      << format(", error/claimed sigma: LiDAR position %.2f rotation %.2f, ",
                s.position_claim.ratio(), s.rotation_claim.ratio())
      << format("%.1f ms", s.time_ms.mean());
  return out.str();
}

std::string to_markdown(const SuiteResult& suite) {
  std::ostringstream out;
  const SuiteOptions& o = suite.options;
  const std::size_t cases = suite.results.empty() ? 0 : suite.results.size() * o.seeds.size();
  out << "Suite `" << suite.suite << "`: seeds " << seeds_text(o.seeds) << ", " << physics_text(o)
      << "; " << cases << " pipeline runs in " << format("%.0f s", suite.seconds)
      << ". Figures: mean over seeds (worst).\n";
  std::string group, published;
  for (const SetupResult& r : suite.results) {
    if (r.setup.group != group) {
      if (!published.empty()) out << "\n" << published << "\n";
      group = r.setup.group;
      published = r.setup.published;
      out << "\n**" << group << "**\n\n"
          << "| set-up | lift | found | false pos. / wrong id | vertex error mm | marker position "
             "mm | marker rotation deg | LiDAR position mm | LiDAR rotation deg |\n"
          << "|---|---|---|---|---|---|---|---|---|\n";
    }
    const Summary& s = r.summary;
    out << "| " << r.setup.name << " | " << lift_name(r.lift) << " | " << found(s) << " | "
        << s.false_positives << " / " << s.wrong_ids << " | " << mm(s.corner_error) << " | "
        << mm(s.marker_position) << " | " << deg(s.marker_rotation_deg) << " | " << mm(s.position)
        << " | " << deg(s.rotation_deg) << " |\n";
  }
  if (!published.empty()) out << "\n" << published << "\n";
  out << "\n" << uncertainty_markdown(suite);
  return out.str();
}

std::string uncertainty_markdown(const SuiteResult& suite) {
  std::ostringstream out;
  out << "**Claimed uncertainty against the observed error** (RMS error over seeds / RMS claimed "
         "sigma = ratio, near 1 when the covariance is right; NEES: mean 6-dof normalised error "
         "squared, 6 expected)\n\n"
      << "| set-up | lift | marker position mm | marker rotation deg | marker NEES | LiDAR "
         "position mm | LiDAR rotation deg | LiDAR NEES |\n"
      << "|---|---|---|---|---|---|---|---|\n";
  const auto claim = [](const Consistency& c, double scale, const char* f) {
    if (c.count == 0) return std::string("-");
    return format(f, c.rms_error() * scale) + " / " + format(f, c.rms_sigma() * scale) + " (" +
           format("%.2f", c.ratio()) + ")";
  };
  for (const SetupResult& r : suite.results) {
    const Summary& s = r.summary;
    if (s.marker_position_claim.count == 0 && s.position_claim.count == 0) continue;
    out << "| " << r.setup.name << " | " << lift_name(r.lift) << " | "
        << claim(s.marker_position_claim, 1000, "%.2f") << " | "
        << claim(s.marker_rotation_claim, 1, "%.3f") << " | "
        << format("%.1f", s.marker_position_claim.mean_nees()) << " | "
        << claim(s.position_claim, 1000, "%.1f") << " | " << claim(s.rotation_claim, 1, "%.3f")
        << " | " << format("%.1f", s.position_claim.mean_nees()) << " |\n";
  }
  return out.str();
}

}  // namespace iilfm::eval
