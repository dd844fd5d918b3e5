#include "support/fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

namespace billiard::testing {

Coordinates scattered_circles(double R, double a, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x5eed5eedULL);
  const double reach = R - a;  // centres must be within this distance of the origin
  std::uniform_real_distribution<double> coordinate(-reach, reach);
  Coordinates c(n, 2);
  long attempts = 0;
  for (int i = 0; i < n; ++i) {
    for (;;) {
      if (++attempts > 100000L * (n + 1)) throw std::runtime_error("scattered_circles: table too dense");
      const double x = coordinate(rng), y = coordinate(rng);
      if (x * x + y * y > reach * reach) continue;
      bool free = true;
      for (int j = 0; j < i && free; ++j) {
        const double dx = x - c(j, 0), dy = y - c(j, 1);
        free = dx * dx + dy * dy >= 4 * a * a;
      }
      if (!free) continue;
      c(i, 0) = x;
      c(i, 1) = y;
      break;
    }
  }
  return c;
}

Velocities gaussian_velocities(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0xfeedULL);
  std::normal_distribution<double> component(0.0, 1.0);
  Velocities v(n, 2);
  for (int i = 0; i < n; ++i) {
    v(i, 0) = component(rng);
    v(i, 1) = component(rng);
  }
  return v;
}

double angular_momentum(const Coordinates& coordinates, const Velocities& velocities) {
  double total = 0;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    total += coordinates(i, 0) * velocities(i, 1) - coordinates(i, 1) * velocities(i, 0);
  }
  return total;
}

double worst_overlap(const Coordinates& coordinates, double a, int* first, int* second) {
  double worst = -std::numeric_limits<double>::infinity();
  int wi = -1, wj = -1;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < coordinates.rows(); ++j) {
      const double overlap = 2 * a - (coordinates.row(i) - coordinates.row(j)).norm();
      if (overlap > worst) {
        worst = overlap;
        wi = static_cast<int>(i);
        wj = static_cast<int>(j);
      }
    }
  }
  if (first) *first = wi;
  if (second) *second = wj;
  return wi < 0 ? 0.0 : worst;
}

double worst_protrusion(const Coordinates& coordinates, double R, double a, int* which) {
  double worst = -std::numeric_limits<double>::infinity();
  int w = -1;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    const double protrusion = coordinates.row(i).norm() + a - R;
    if (protrusion > worst) {
      worst = protrusion;
      w = static_cast<int>(i);
    }
  }
  if (which) *which = w;
  return w < 0 ? 0.0 : worst;
}

ScratchFolder::ScratchFolder() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "billiard-test";
  if (info) name += std::string("-") + info->test_suite_name() + "-" + info->name();
  std::random_device entropy;
  path_ = std::filesystem::temp_directory_path() / (name + "-" + std::to_string(entropy()));
  std::filesystem::create_directories(path_);
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace billiard::testing
