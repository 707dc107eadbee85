// odoloc_regmap_gen: regmap/odoloc.yaml -> C++ headers (registers, fabric
// ports, the C++14 map of the HLS kernels), C header, SystemRDL, Markdown.
// Exits 1 with the reason when the description is inconsistent.
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <sstream>

#include "odoloc/output/output_file.hpp"
#include "odoloc/regmap/regmap.hpp"

namespace {

// Rewrites a file only when its text changes, so builds stay incremental.
void write_if_changed(const std::string& path, const std::string& text) {
  if (path.empty())
    return;
  std::ifstream in(path);
  std::ostringstream old;
  old << in.rdbuf();
  if (in && old.str() == text)
    return;
  // Whole or not at all: a build interrupted here leaves the old header.
  try {
    odoloc::output::write_file(path, text);
  } catch (const odoloc::output::OutputError& e) {
    throw odoloc::regmap::RegmapError(e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"odoloc register-map generator"};
  std::string input, cpp, ports, logic_ports, hls, c, rdl, markdown;
  app.add_option("--input", input, "register description (YAML)")->required();
  app.add_option("--cpp", cpp, "C++ header to write");
  app.add_option("--ports", ports, "C++ header of the fabric's typed ports to write");
  app.add_option("--logic-ports", logic_ports,
                 "C++14 header of the ports over an integer-type family to write");
  app.add_option("--hls", hls, "C++14 header of the map for the HLS kernels to write");
  app.add_option("--c", c, "C header to write");
  app.add_option("--rdl", rdl, "SystemRDL 2.0 file to write");
  app.add_option("--markdown", markdown, "Markdown documentation to write");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto map = odoloc::regmap::load(input);
    write_if_changed(cpp, odoloc::regmap::emit_cpp(map));
    write_if_changed(ports, odoloc::regmap::emit_ports(map));
    write_if_changed(logic_ports, odoloc::regmap::emit_logic_ports(map));
    write_if_changed(hls, odoloc::regmap::emit_hls(map));
    write_if_changed(c, odoloc::regmap::emit_c(map));
    write_if_changed(rdl, odoloc::regmap::emit_systemrdl(map));
    write_if_changed(markdown, odoloc::regmap::emit_markdown(map));
  } catch (const odoloc::regmap::RegmapError& e) {
    std::cerr << "odoloc_regmap_gen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
