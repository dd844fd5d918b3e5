// svg_circles FILE: the circles a browser draws in an SVG file, as the graded suites' SVG reader
// (svg_reader.hpp) sees them: one JSON object per line, {"x", "y", "radius", "attributes"} with
// the centre and radius in the root's user coordinates (transforms applied). The grader's tests
// read the pictures of failing cases back with it. Exit status 1 and the reader's message on
// standard error for a file the reader refuses.
#include "support/json_text.hpp"
#include "support/svg_reader.hpp"

#include <cstdio>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: svg_circles FILE\n";
    return 2;
  }
  try {
    const auto document = billiard::testing::read_svg(argv[1]);
    std::cout.precision(17);
    for (const auto* circle : document.rendered_circles()) {
      std::cout << "{\"x\": " << circle->x << ", \"y\": " << circle->y << ", \"radius\": " << circle->radius
                << ", \"attributes\": {";
      bool first = true;
      for (const auto& [name, value] : circle->attributes) {
        std::cout << (first ? "" : ", ") << billiard::testing::json_string(name) << ": " << billiard::testing::json_string(value);
        first = false;
      }
      std::cout << "}}\n";
    }
  } catch (const billiard::testing::SvgError& error) {
    std::cerr << "svg_circles: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
