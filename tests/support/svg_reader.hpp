// A small reader for the SVG files the course tasks write (visualize_table, movie). The XML is
// read by pugixml; the reader finds the <circle> elements in it, where they are drawn and how
// they are animated:
//   - XML as a browser reads it: the <?xml ...?> declaration, processing instructions, comments,
//     <!DOCTYPE ...>, CDATA sections and text are skipped; element names may carry a namespace
//     prefix (svg:circle); attributes in any order, with single or double quotes, and entities
//     (&amp; &lt; &#65; ...) decoded;
//   - <circle> cx, cy, r as numbers, optionally with a unit (px, or the absolute units mm, cm,
//     in, pt, pc, converted to px); a missing cx or cy is 0, as in SVG;
//   - transform="..." on <svg>, <g>, <a>, <circle> (translate, scale, rotate, skewX, skewY,
//     matrix), composed from the root down; anything else is reported as an error that says what
//     the reader understands, but only if a circle is drawn under it;
//   - <animate> children of circles (attributeName, values, keyTimes, dur, calcMode, ...), and
//     sampling them at a fraction of their duration by the SMIL rules for linear animation.
// Files a browser would refuse (tags that do not match, text or a second element outside the
// root, duplicate attributes) are refused as well, with the line number and a plain message.
// pugixml finds most of these; text or a second element outside the root and duplicate
// attributes, which it accepts, are checked by the reader.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace billiard::testing {

// Every problem the reader finds: a message for a student, starting with "line N:" when it
// belongs to a place in the file.
class SvgError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // The line of the file the problem is on (the message's "line N:"), or 0 when it names none.
  int line() const;
};

// An affine map x' = a x + c y + e, y' = b x + d y + f (SVG's matrix(a b c d e f)).
struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;

  // The map that applies `inner` first, then this one.
  Affine then_inner(const Affine& inner) const;
  std::array<double, 2> apply(double x, double y) const;
  // How lengths scale: sqrt(|det|). Exact for similarities (rotation, uniform scale, flips).
  double length_scale() const;
  // True if circles stay circles (a rotation or flip times a uniform scale), up to rounding.
  bool keeps_circles_round() const;
};

// One <animate> element that is a child of a <circle>.
struct SvgAnimation {
  int line = 0;                                  // line of the <animate> tag
  std::map<std::string, std::string> attributes;  // all of them, entities decoded
  std::string attribute_name;                    // attributeName, "" if absent
  std::string calc_mode;                         // calcMode, "" if absent (SVG's default: linear)
  std::string dur;                               // dur as written, "" if absent
  std::string repeat_count;                      // repeatCount, "" if absent
  std::string begin;                             // begin, "" if absent
  bool has_values = false;                       // a values="..." attribute is present
  std::vector<std::string> values;               // values split on ';' (trimmed)
  bool has_key_times = false;                    // a keyTimes="..." attribute is present
  std::vector<std::string> key_times;            // keyTimes split on ';' (trimmed)

  bool has(std::string_view attribute) const;
  // dur in seconds (SMIL clock value: "12.5s", "500ms", "2min", "1h", "12.5", "01:02.5",
  // "0:01:02.5"); NaN if absent or not a clock value (e.g. "indefinite").
  double dur_seconds() const;
  // begin in seconds: 0 if absent, NaN if not a plain clock value (e.g. "click").
  double begin_seconds() const;
};

// One <circle> element.
struct SvgCircle {
  int line = 0;                                  // line of the <circle> tag
  std::map<std::string, std::string> attributes;  // all of them, entities decoded
  std::vector<std::string> ancestors;            // element names from the root down to the parent
  bool rendered = true;  // false inside <defs>, <clipPath>, <mask>, <symbol>, <pattern>, <marker>
  double cx = 0, cy = 0, r = 0;                  // the attributes in px (0 when absent)
  bool has_r = false;
  Affine transform;  // from the circle's own coordinates to the root <svg>'s user coordinates
  double x = 0, y = 0, radius = 0;  // centre and radius after `transform`
  std::vector<SvgAnimation> animations;          // its <animate> children, in order

  // The <animate> children whose attributeName is `attribute`.
  std::vector<const SvgAnimation*> animations_of(std::string_view attribute) const;
  // Centre in root user coordinates for local coordinates (cx, cy).
  std::array<double, 2> map(double local_cx, double local_cy) const { return transform.apply(local_cx, local_cy); }
};

struct SvgDocument {
  std::string root_name;                              // local name of the root element ("svg")
  std::map<std::string, std::string> root_attributes;  // e.g. xmlns, width, viewBox
  std::vector<SvgCircle> circles;                     // every <circle>, in document order
  std::string text;                                   // the file as read, for showing its lines

  // The circles a browser draws (not inside <defs>, <clipPath>, ...).
  std::vector<const SvgCircle*> rendered_circles() const;
};

// Parses SVG text; throws SvgError with a student-readable message.
SvgDocument parse_svg(std::string_view text);
// Reads and parses a file; throws SvgError if it cannot be read or parsed.
SvgDocument read_svg(const std::filesystem::path& file);

// A number with an optional unit (px, mm, cm, in, pt, pc), in px; throws SvgError naming
// `what` otherwise (percentages and font-relative units are refused: they depend on the viewer).
double parse_length(std::string_view text, std::string_view what);

// The value of a linear (or paced-free) SMIL animation at `fraction` (0 to 1) of its simple
// duration: the values at keyTimes, linear in between, and evenly spaced when keyTimes is
// absent; from/to/by are understood too (`base` is the animated attribute's own value, for
// "to" and "by" animations). Throws SvgError for calcMode other than linear, for lists that do
// not fit together (as browsers ignore such animations), or for values that are not numbers.
double sample_animation(const SvgAnimation& animation, double fraction, double base);

}  // namespace billiard::testing
