// particles_reference FILE END_TIME [--physical]: the independent implementation as a program,
// for writing the examples' expected outputs (tests only; no checks of the file).
#include "reference.hpp"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: particles_reference FILE END_TIME [--physical]\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  particles_reference::Box box;
  std::size_t n = 0;
  in >> n >> box.radius >> box.lx >> box.ly;
  box.particles.resize(n);
  for (auto& p : box.particles) in >> p.x >> p.y >> p.u >> p.v;
  if (!in) {
    std::cerr << "particles_reference: cannot read " << argv[1] << "\n";
    return 2;
  }
  std::cout << particles_reference::run(box, std::strtod(argv[2], nullptr), argc > 3 && std::string(argv[3]) == "--physical").output;
  return 0;
}
