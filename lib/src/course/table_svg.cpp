#include "billiard/table_svg.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace billiard {

TableSvg::TableSvg(double table_radius, double room_below, int width)
    : table_radius_(table_radius),
      corner_(-1.05 * table_radius),
      bottom_(1.05 * table_radius + room_below * table_radius),
      width_(width) {
  body_.precision(10);
}

void TableSvg::title(std::string_view text) { body_ << "  <title>" << escaped(text) << "</title>\n"; }

void TableSvg::metadata(std::string_view text) { body_ << "  <metadata>" << escaped(text) << "</metadata>\n"; }

void TableSvg::table(std::string_view fill, std::string_view attributes) {
  body_ << "  <circle cx=\"0\" cy=\"0\" r=\"" << table_radius_ << "\" fill=\"" << fill << "\" stroke=\""
        << kWallColour << "\" stroke-width=\"" << 2 * unit() << "\" " << attributes << "/>\n";
}

void TableSvg::wall(const Wall& wall, std::string_view attributes) {
  line(wall.a, wall.b,
       std::string("stroke=\"") + kWallColour + "\" stroke-width=\"" + std::to_string(2 * unit()) +
           "\" stroke-linecap=\"round\" " + std::string(attributes));
}

void TableSvg::line(const Vector& from, const Vector& to, std::string_view attributes) {
  body_ << "  <line x1=\"" << from(0) << "\" y1=\"" << svg_y(from(1)) << "\" x2=\"" << to(0) << "\" y2=\""
        << svg_y(to(1)) << "\" " << attributes << "/>\n";
}

void TableSvg::circle(const Vector& centre, double radius, std::string_view attributes, std::string_view children) {
  body_ << "  <circle cx=\"" << centre(0) << "\" cy=\"" << svg_y(centre(1)) << "\" r=\"" << radius << "\" "
        << attributes;
  if (children.empty()) {
    body_ << "/>\n";
  } else {
    body_ << ">" << children << "</circle>\n";
  }
}

void TableSvg::arrow(const Vector& from, const Vector& to, std::string_view colour, double width,
                     std::string_view attributes) {
  const Vector along = to - from;
  const double length = along.norm();
  if (!(length > 0) || !std::isfinite(length)) return;
  // The head: a triangle 4 widths long and 3 wide at the tip, never longer than half the arrow.
  const double head = std::min(4 * width, length / 2);
  const Vector direction = along / length, across(-direction(1), direction(0));
  const Vector base = to - head * direction;
  line(from, base,
       std::string("stroke=\"") + std::string(colour) + "\" stroke-width=\"" + std::to_string(width) + "\" " +
           std::string(attributes));
  const Vector left = base + 0.4 * head * across, right = base - 0.4 * head * across;
  body_ << "  <polygon points=\"" << to(0) << ',' << svg_y(to(1)) << ' ' << left(0) << ',' << svg_y(left(1)) << ' '
        << right(0) << ',' << svg_y(right(1)) << "\" fill=\"" << colour << "\" " << attributes << "/>\n";
}

void TableSvg::text(const Vector& at, std::string_view text, double size, std::string_view attributes) {
  body_ << "  <text x=\"" << at(0) << "\" y=\"" << svg_y(at(1)) << "\" font-size=\"" << size
        << "\" font-family=\"sans-serif\" " << attributes << ">" << escaped(text) << "</text>\n";
}

std::string TableSvg::str() const {
  std::ostringstream svg;
  svg.precision(10);
  const double size = -2 * corner_, height = bottom_ - corner_;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << (fit_window_ ? "100%" : std::to_string(width_))
      << "\" height=\"" << (fit_window_ ? "100%" : std::to_string(std::lround(width_ * height / size)))
      << "\" viewBox=\"" << corner_ << ' ' << corner_ << ' ' << size << ' ' << height << "\">\n"
      << body_.str() << "</svg>\n";
  return svg.str();
}

void TableSvg::write(const std::filesystem::path& file) const {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out << str();
  if (!out.flush()) throw std::runtime_error("writing " + file.string() + " failed");
}

std::string TableSvg::escaped(std::string_view text) {
  std::string result;
  result.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': result += "&amp;"; break;
      case '<': result += "&lt;"; break;
      case '>': result += "&gt;"; break;
      case '"': result += "&quot;"; break;
      default: result += c;
    }
  }
  return result;
}

}  // namespace billiard
