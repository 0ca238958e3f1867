// `iilfm marker print FAMILY ID --size M`: printable markers for every supported family, and
// `iilfm marker families`: their names.
#include <fstream>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"
#include "marker_print.hpp"

namespace iilfm::cli {

namespace {

struct PrintArgs {
  MarkerPrintRequest request;
  std::string png_path, svg_path;
};

// "apriltag:tag36h11" id 7 -> "apriltag_tag36h11_7.png".
std::string default_png_name(const MarkerPrintRequest& r) {
  std::string name = r.family;
  for (char& c : name)
    if (c == ':') c = '_';
  return name + "_" + std::to_string(r.id) + ".png";
}

int run_print(PrintArgs& a) {
  family_layout(a.request.family);  // names the family's back-end in the error when unknown
  const MarkerPrint print = render_marker_print(a.request);
  if (a.png_path.empty()) a.png_path = default_png_name(a.request);
  write_png_with_dpi(a.png_path, print.image, a.request.dpi);
  std::cout << "wrote " << a.png_path << ": " << print.image.cols << "x" << print.image.rows
            << " px, " << (a.request.family.rfind("rings:", 0) == 0 ? "diameter " : "square ")
            << print.square.width << " px = " << a.request.size_m << " m at " << a.request.dpi
            << " dpi (" << print.cell_px << " px per cell)\n";
  if (!a.svg_path.empty()) {
    std::ofstream file(a.svg_path);
    if (!file || !(file << render_marker_svg(a.request)) || !file.flush())
      throw file_error(a.svg_path, "cannot write the SVG");
    std::cout << "wrote " << a.svg_path << "\n";
  }
  return 0;
}

}  // namespace

Runner register_marker_command(CLI::App& app) {
  CLI::App* marker = app.add_subcommand("marker", "Printable markers");
  marker->require_subcommand(1);
  auto args = std::make_shared<PrintArgs>();
  CLI::App* print = marker->add_subcommand(
      "print", "Write a marker image whose square is --size metres when printed at --dpi");
  print->add_option("family", args->request.family, "Marker family, e.g. apriltag:tag36h11")
      ->required();
  print->add_option("id", args->request.id, "Marker id")->required();
  print
      ->add_option("--size", args->request.size_m,
                   "Edge of the marker's square in metres (the black square; rings: the outer "
                   "diameter; docs/detectors.md)")
      ->required();
  print->add_option("--dpi", args->request.dpi, "Print resolution")->capture_default_str();
  print->add_option("--out", args->png_path, "PNG file (default FAMILY_ID.png)");
  print->add_option("--svg", args->svg_path, "Also write a vector SVG at the same size");
  CLI::App* families = marker->add_subcommand("families", "List every supported family");
  return [args, print, families]() -> int {
    if (print->parsed()) return run_print(*args);
    if (families->parsed()) {
      for (const std::string& name : known_families()) std::cout << name << "\n";
      return 0;
    }
    return 2;
  };
}

}  // namespace iilfm::cli
