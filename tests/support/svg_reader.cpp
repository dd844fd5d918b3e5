#include "support/svg_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

namespace billiard::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

template <typename... Parts>
std::string str(const Parts&... parts) {
  std::ostringstream out;
  out.precision(10);
  (out << ... << parts);
  return out.str();
}

[[noreturn]] void fail_at(int line, const std::string& message) {
  throw SvgError(str("line ", line, ": ", message));
}

bool is_space(char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; }

std::string_view trim(std::string_view text) {
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

// Parses a number at the start of `text` (SVG number syntax: optional sign, digits, fraction,
// exponent); returns it and removes it from `text`, or nullopt if there is none.
std::optional<double> take_number(std::string_view& text) {
  std::string_view rest = text;
  bool plus = false;
  if (!rest.empty() && rest.front() == '+') {
    plus = true;
    rest.remove_prefix(1);
  }
  if (rest.empty() || (plus && rest.front() == '-')) return std::nullopt;
  double value = 0;
  const auto result = std::from_chars(rest.data(), rest.data() + rest.size(), value);
  if (result.ec != std::errc()) {
    // from_chars refuses out-of-range numbers; SVG files should not contain them anyway.
    return std::nullopt;
  }
  text.remove_prefix(static_cast<std::size_t>(result.ptr - text.data()));
  return value;
}

// Splits an SMIL list ("1;2;3", spaces allowed, one trailing ';' tolerated).
std::vector<std::string> split_semicolons(std::string_view list) {
  std::vector<std::string> items;
  list = trim(list);
  if (list.empty()) return items;
  if (list.back() == ';') list.remove_suffix(1);
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = list.find(';', start);
    items.emplace_back(trim(list.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return items;
}

// Decodes the five predefined XML entities and numeric character references (ASCII only; other
// references are kept as written).
std::string decode_entities(std::string_view raw) {
  std::string out;
  out.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '&') {
      out += raw[i];
      continue;
    }
    const std::size_t semicolon = raw.find(';', i);
    if (semicolon == std::string_view::npos || semicolon - i > 10) {
      out += raw[i];
      continue;
    }
    const std::string_view name = raw.substr(i + 1, semicolon - i - 1);
    char replacement = 0;
    if (name == "lt") replacement = '<';
    else if (name == "gt") replacement = '>';
    else if (name == "amp") replacement = '&';
    else if (name == "quot") replacement = '"';
    else if (name == "apos") replacement = '\'';
    else if (name.size() > 1 && name[0] == '#') {
      long code = -1;
      const bool hex = name[1] == 'x' || name[1] == 'X';
      const std::string_view digits = name.substr(hex ? 2 : 1);
      const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), code, hex ? 16 : 10);
      if (result.ec == std::errc() && result.ptr == digits.data() + digits.size() && code > 0 && code < 128) {
        replacement = static_cast<char>(code);
      }
    }
    if (replacement == 0) {
      out += raw[i];
      continue;
    }
    out += replacement;
    i = semicolon;
  }
  return out;
}

std::string local_name(std::string_view name) {
  const std::size_t colon = name.find(':');
  return std::string(colon == std::string_view::npos ? name : name.substr(colon + 1));
}

bool hides_children(std::string_view name) {
  return name == "defs" || name == "clipPath" || name == "mask" || name == "symbol" || name == "pattern" ||
         name == "marker";
}

// Parses a transform list; returns an error message (empty on success) and sets `result`.
std::string parse_transform(std::string_view text, Affine& result) {
  const std::string understood =
      "the test reader understands translate(x y), scale(s) or scale(sx sy), rotate(angle [cx cy]), "
      "skewX(angle), skewY(angle) and matrix(a b c d e f), with numbers separated by spaces or commas";
  Affine total;
  std::string_view rest = text;
  auto skip_separators = [&rest] {
    while (!rest.empty() && (is_space(rest.front()) || rest.front() == ',')) rest.remove_prefix(1);
  };
  skip_separators();
  while (!rest.empty()) {
    std::size_t name_end = 0;
    while (name_end < rest.size() && std::isalpha(static_cast<unsigned char>(rest[name_end]))) ++name_end;
    const std::string name(rest.substr(0, name_end));
    rest.remove_prefix(name_end);
    while (!rest.empty() && is_space(rest.front())) rest.remove_prefix(1);
    if (name.empty() || rest.empty() || rest.front() != '(') {
      return str("transform=\"", text, "\" is not a list of transform functions; ", understood);
    }
    rest.remove_prefix(1);
    std::vector<double> args;
    for (;;) {
      skip_separators();
      if (!rest.empty() && rest.front() == ')') {
        rest.remove_prefix(1);
        break;
      }
      const auto number = take_number(rest);
      if (!number) return str("transform=\"", text, "\": cannot read the arguments of ", name, "(...); ", understood);
      double value = *number;
      // CSS-style units, which browsers accept in the attribute too.
      if (rest.substr(0, 3) == "deg") rest.remove_prefix(3);
      else if (rest.substr(0, 2) == "px") rest.remove_prefix(2);
      args.push_back(value);
    }
    Affine m;
    const std::size_t count = args.size();
    auto radians = [](double degrees) { return degrees * kPi / 180; };
    if (name == "matrix" && count == 6) {
      m = Affine{args[0], args[1], args[2], args[3], args[4], args[5]};
    } else if (name == "translate" && (count == 1 || count == 2)) {
      m.e = args[0];
      m.f = count == 2 ? args[1] : 0;
    } else if (name == "scale" && (count == 1 || count == 2)) {
      m.a = args[0];
      m.d = count == 2 ? args[1] : args[0];
    } else if (name == "rotate" && (count == 1 || count == 3)) {
      const double angle = radians(args[0]);
      Affine rotation{std::cos(angle), std::sin(angle), -std::sin(angle), std::cos(angle), 0, 0};
      if (count == 3) {
        const Affine to{1, 0, 0, 1, args[1], args[2]}, back{1, 0, 0, 1, -args[1], -args[2]};
        rotation = to.then_inner(rotation).then_inner(back);
      }
      m = rotation;
    } else if (name == "skewX" && count == 1) {
      m.c = std::tan(radians(args[0]));
    } else if (name == "skewY" && count == 1) {
      m.b = std::tan(radians(args[0]));
    } else {
      return str("transform=\"", text, "\" uses ", name, "(...) with ", count, " argument(s); ", understood);
    }
    total = total.then_inner(m);
    skip_separators();
  }
  result = total;
  return "";
}

double parse_clock_value(std::string_view text) {
  text = trim(text);
  if (text.empty()) return kNaN;
  if (text.find(':') != std::string_view::npos) {
    // Full or partial clock value: [hh:]mm:ss[.fraction].
    std::vector<double> parts;
    std::size_t start = 0;
    for (;;) {
      const std::size_t end = text.find(':', start);
      std::string_view part = text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
      const auto number = take_number(part);
      if (!number || !part.empty() || *number < 0) return kNaN;
      parts.push_back(*number);
      if (end == std::string_view::npos) break;
      start = end + 1;
    }
    if (parts.size() == 2) return parts[0] * 60 + parts[1];
    if (parts.size() == 3) return parts[0] * 3600 + parts[1] * 60 + parts[2];
    return kNaN;
  }
  std::string_view rest = text;
  const auto number = take_number(rest);
  if (!number) return kNaN;
  rest = trim(rest);
  if (rest.empty() || rest == "s") return *number;
  if (rest == "ms") return *number / 1000;
  if (rest == "min") return *number * 60;
  if (rest == "h") return *number * 3600;
  return kNaN;
}

struct Frame {
  std::string name;  // local name
  int line = 0;
  Affine transform;
  std::string transform_error;  // set if this element or an ancestor has a transform we cannot read
  bool hidden = false;
  int circle = -1;  // index into the document's circles if this element is a circle
};

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {}

  SvgDocument parse() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;  // UTF-8 byte order mark
    while (pos_ < text_.size()) {
      if (starts_with("<?")) {
        skip_past("?>", "a processing instruction <?...");
      } else if (starts_with("<!--")) {
        skip_past("-->", "a comment <!--");
      } else if (starts_with("<![CDATA[")) {
        if (stack_.empty()) fail_at(line(), "a CDATA section outside the <svg> element");
        skip_past("]]>", "a CDATA section <![CDATA[");
      } else if (starts_with("<!")) {
        skip_declaration();
      } else if (starts_with("</")) {
        end_tag();
      } else if (text_[pos_] == '<') {
        start_tag();
      } else {
        text_content();
      }
    }
    if (!stack_.empty()) {
      const Frame& open = stack_.back();
      fail_at(open.line, str("<", open.name, "> is never closed: the file ends before its </", open.name,
                             "> (did the program stop writing early, or forget to close the file?)"));
    }
    if (!seen_root_) {
      throw SvgError("the file contains no element at all (it is empty or only has comments); expected <svg ...> ... </svg>");
    }
    return std::move(document_);
  }

 private:
  bool starts_with(std::string_view prefix) const { return text_.substr(pos_, prefix.size()) == prefix; }

  // Line of position `at` (positions are asked for in increasing order, mostly).
  int line(std::size_t at) {
    if (at < line_pos_) {
      line_pos_ = 0;
      line_ = 1;
    }
    for (; line_pos_ < at && line_pos_ < text_.size(); ++line_pos_) {
      if (text_[line_pos_] == '\n') ++line_;
    }
    return line_;
  }
  int line() { return line(pos_); }

  void skip_past(std::string_view end, std::string_view what) {
    const std::size_t found = text_.find(end, pos_);
    if (found == std::string_view::npos) fail_at(line(), str(what, " is never closed with ", end));
    pos_ = found + end.size();
  }

  // <!DOCTYPE ...> possibly with an internal subset [...].
  void skip_declaration() {
    const int start_line = line();
    int brackets = 0;
    char quote = 0;
    for (std::size_t i = pos_ + 2; i < text_.size(); ++i) {
      const char ch = text_[i];
      if (quote) {
        if (ch == quote) quote = 0;
      } else if (ch == '"' || ch == '\'') {
        quote = ch;
      } else if (ch == '[') {
        ++brackets;
      } else if (ch == ']') {
        --brackets;
      } else if (ch == '>' && brackets <= 0) {
        pos_ = i + 1;
        return;
      }
    }
    fail_at(start_line, "a declaration <!...> (such as <!DOCTYPE ...>) is never closed with >");
  }

  void text_content() {
    const std::size_t next = text_.find('<', pos_);
    const std::size_t end = next == std::string_view::npos ? text_.size() : next;
    if (stack_.empty()) {
      const std::string_view content = trim(text_.substr(pos_, end - pos_));
      if (!content.empty()) {
        std::string shown(content.substr(0, 40));
        std::size_t first = pos_;
        while (is_space(text_[first])) ++first;
        fail_at(line(first),
                str("text \"", shown, content.size() > 40 ? "..." : "", "\" outside the <svg> element: ",
                    seen_root_ ? "nothing but comments may follow </svg> (was the file appended to instead of overwritten?)"
                               : "nothing but <?xml ...?>, <!DOCTYPE ...> and comments may come before <svg>"));
      }
    }
    pos_ = end;
  }

  std::string take_name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '>' && text_[pos_] != '/' &&
           text_[pos_] != '=' && text_[pos_] != '<' && text_[pos_] != '"' && text_[pos_] != '\'') {
      ++pos_;
    }
    return std::string(text_.substr(start, pos_ - start));
  }

  void skip_spaces() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
  }

  void end_tag() {
    const int tag_line = line();
    pos_ += 2;
    const std::string name = local_name(take_name());
    skip_spaces();
    if (pos_ >= text_.size() || text_[pos_] != '>') fail_at(tag_line, str("the end tag </", name, " is not closed with >"));
    ++pos_;
    if (stack_.empty()) fail_at(tag_line, str("</", name, "> has no matching <", name, "> before it"));
    const Frame& open = stack_.back();
    if (open.name != name) {
      fail_at(tag_line, str("</", name, "> closes <", open.name, "> (opened on line ", open.line,
                            "): tags must be closed in the reverse order they were opened, and an element "
                            "without children is written <", open.name, " ... />"));
    }
    stack_.pop_back();
  }

  void start_tag() {
    const int tag_line = line();
    ++pos_;
    const std::string full_name = take_name();
    if (full_name.empty()) {
      fail_at(tag_line, "'<' is not followed by an element name (a literal < in text must be written &lt;)");
    }
    const std::string name = local_name(full_name);
    std::map<std::string, std::string> attributes;
    bool self_closing = false;
    for (;;) {
      skip_spaces();
      if (pos_ >= text_.size()) fail_at(tag_line, str("the tag <", name, " is never closed with > or />"));
      const char ch = text_[pos_];
      if (ch == '>') {
        ++pos_;
        break;
      }
      if (ch == '/') {
        if (pos_ + 1 < text_.size() && text_[pos_ + 1] == '>') {
          pos_ += 2;
          self_closing = true;
          break;
        }
        fail_at(line(), str("in <", name, ">: '/' must be followed by '>'"));
      }
      const int attribute_line = line();
      const std::string attribute = take_name();
      if (attribute.empty()) fail_at(attribute_line, str("in <", name, ">: unexpected character '", ch, "'"));
      skip_spaces();
      if (pos_ >= text_.size() || text_[pos_] != '=') {
        fail_at(attribute_line, str("in <", name, ">: attribute ", attribute, " has no value (write ", attribute, "=\"...\")"));
      }
      ++pos_;
      skip_spaces();
      if (pos_ >= text_.size() || (text_[pos_] != '"' && text_[pos_] != '\'')) {
        fail_at(attribute_line, str("in <", name, ">: the value of ", attribute,
                                    " must be in quotes, e.g. ", attribute, "=\"12.5\""));
      }
      const char quote = text_[pos_];
      const std::size_t close = text_.find(quote, pos_ + 1);
      if (close == std::string_view::npos) fail_at(attribute_line, str("in <", name, ">: the value of ", attribute, " is never closed with ", quote));
      const std::string value = decode_entities(text_.substr(pos_ + 1, close - pos_ - 1));
      pos_ = close + 1;
      if (!attributes.emplace(attribute, value).second) {
        fail_at(attribute_line, str("<", name, "> has the attribute ", attribute, " twice"));
      }
    }
    open_element(name, tag_line, std::move(attributes), self_closing);
  }

  void open_element(const std::string& name, int tag_line, std::map<std::string, std::string> attributes,
                    bool self_closing) {
    Frame frame;
    frame.name = name;
    frame.line = tag_line;
    if (stack_.empty()) {
      if (seen_root_) {
        fail_at(tag_line, str("a second top-level element <", name, "> after </", document_.root_name,
                              ">: a file holds one picture (was the file appended to instead of overwritten?)"));
      }
      seen_root_ = true;
      if (name != "svg") {
        fail_at(tag_line, str("the file's top-level element is <", name, ">; an SVG file's must be <svg ...>"));
      }
      document_.root_name = name;
      document_.root_attributes = attributes;
    } else {
      const Frame& parent = stack_.back();
      frame.transform = parent.transform;
      frame.transform_error = parent.transform_error;
      frame.hidden = parent.hidden;
      if (name == "svg" && frame.transform_error.empty()) {
        frame.transform_error = str("line ", tag_line, ": an <svg> inside <svg> starts a new viewport, which the test reader does not understand; "
                                    "draw everything in one <svg> and use <g transform=\"...\"> to move or scale");
      }
    }
    if (hides_children(name)) frame.hidden = true;
    if (const auto it = attributes.find("transform"); it != attributes.end() && frame.transform_error.empty()) {
      Affine own;
      const std::string error = parse_transform(it->second, own);
      if (error.empty()) {
        frame.transform = frame.transform.then_inner(own);
      } else {
        frame.transform_error = str("line ", tag_line, ": ", error);
      }
    }

    if (name == "circle") {
      if (!frame.transform_error.empty()) throw SvgError(frame.transform_error);
      SvgCircle circle;
      circle.line = tag_line;
      for (const Frame& ancestor : stack_) circle.ancestors.push_back(ancestor.name);
      circle.rendered = !frame.hidden;
      auto length = [&](const char* attribute, double& out) {
        const auto it = attributes.find(attribute);
        if (it == attributes.end()) return false;
        try {
          out = parse_length(it->second, str("the attribute ", attribute));
        } catch (const SvgError& error) {
          fail_at(tag_line, str("in <circle>: ", error.what()));
        }
        return true;
      };
      length("cx", circle.cx);
      length("cy", circle.cy);
      circle.has_r = length("r", circle.r);
      circle.attributes = std::move(attributes);
      circle.transform = frame.transform;
      const auto centre = circle.transform.apply(circle.cx, circle.cy);
      circle.x = centre[0];
      circle.y = centre[1];
      circle.radius = circle.r * circle.transform.length_scale();
      frame.circle = static_cast<int>(document_.circles.size());
      document_.circles.push_back(std::move(circle));
    } else if (name == "animate" && !stack_.empty() && stack_.back().circle >= 0) {
      SvgAnimation animation;
      animation.line = tag_line;
      auto get = [&attributes](const char* attribute) {
        const auto it = attributes.find(attribute);
        return it == attributes.end() ? std::string() : std::string(trim(it->second));
      };
      animation.attribute_name = get("attributeName");
      animation.calc_mode = get("calcMode");
      animation.dur = get("dur");
      animation.repeat_count = get("repeatCount");
      animation.begin = get("begin");
      if (const auto it = attributes.find("values"); it != attributes.end()) {
        animation.has_values = true;
        animation.values = split_semicolons(it->second);
      }
      if (const auto it = attributes.find("keyTimes"); it != attributes.end()) {
        animation.has_key_times = true;
        animation.key_times = split_semicolons(it->second);
      }
      animation.attributes = std::move(attributes);
      document_.circles[static_cast<std::size_t>(stack_.back().circle)].animations.push_back(std::move(animation));
    }
    if (!self_closing) stack_.push_back(std::move(frame));
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_pos_ = 0;
  int line_ = 1;
  bool seen_root_ = false;
  std::vector<Frame> stack_;
  SvgDocument document_;
};

}  // namespace

Affine Affine::then_inner(const Affine& in) const {
  return Affine{a * in.a + c * in.b, b * in.a + d * in.b, a * in.c + c * in.d,
                b * in.c + d * in.d, a * in.e + c * in.f + e, b * in.e + d * in.f + f};
}

std::array<double, 2> Affine::apply(double x, double y) const { return {a * x + c * y + e, b * x + d * y + f}; }

double Affine::length_scale() const { return std::sqrt(std::abs(a * d - b * c)); }

bool Affine::keeps_circles_round() const {
  const double size = a * a + b * b + c * c + d * d;
  if (!(size > 0)) return false;
  return std::abs((a * a + b * b) - (c * c + d * d)) <= 1e-6 * size && std::abs(a * c + b * d) <= 1e-6 * size;
}

bool SvgAnimation::has(std::string_view attribute) const { return attributes.count(std::string(attribute)) > 0; }

double SvgAnimation::dur_seconds() const { return parse_clock_value(dur); }

double SvgAnimation::begin_seconds() const { return begin.empty() ? 0.0 : parse_clock_value(begin); }

std::vector<const SvgAnimation*> SvgCircle::animations_of(std::string_view attribute) const {
  std::vector<const SvgAnimation*> found;
  for (const auto& animation : animations) {
    if (animation.attribute_name == attribute) found.push_back(&animation);
  }
  return found;
}

std::vector<const SvgCircle*> SvgDocument::rendered_circles() const {
  std::vector<const SvgCircle*> found;
  for (const auto& circle : circles) {
    if (circle.rendered) found.push_back(&circle);
  }
  return found;
}

SvgDocument parse_svg(std::string_view text) { return Parser(text).parse(); }

SvgDocument read_svg(const std::filesystem::path& file) {
  std::error_code error;
  if (!std::filesystem::exists(file, error)) throw SvgError(str("the file ", file, " does not exist: it was not written"));
  if (!std::filesystem::is_regular_file(file, error)) throw SvgError(str(file, " is not a regular file"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SvgError(str("cannot open ", file, " for reading"));
  std::ostringstream content;
  content << in.rdbuf();
  const std::string text = content.str();
  if (trim(text).empty()) throw SvgError(str("the file ", file, " is empty: nothing was written into it (was the stream flushed and closed?)"));
  try {
    return parse_svg(text);
  } catch (const SvgError& problem) {
    throw SvgError(str(file.filename().string(), ", ", problem.what()));
  }
}

double parse_length(std::string_view text, std::string_view what) {
  std::string_view rest = trim(text);
  const auto number = take_number(rest);
  if (!number) throw SvgError(str(what, " = \"", text, "\" is not a number"));
  rest = trim(rest);
  double factor = 1;
  if (rest.empty() || rest == "px") factor = 1;
  else if (rest == "in") factor = 96;
  else if (rest == "cm") factor = 96 / 2.54;
  else if (rest == "mm") factor = 96 / 25.4;
  else if (rest == "pt") factor = 96.0 / 72;
  else if (rest == "pc") factor = 16;
  else {
    throw SvgError(str(what, " = \"", text, "\": the unit \"", rest,
                       "\" depends on the viewer; write plain numbers (user units, i.e. px)"));
  }
  if (!std::isfinite(*number)) throw SvgError(str(what, " = \"", text, "\" is not a finite number"));
  return *number * factor;
}

double sample_animation(const SvgAnimation& animation, double fraction, double base) {
  const std::string where = str("line ", animation.line, ": <animate attributeName=\"", animation.attribute_name, "\">");
  const bool single_value = animation.has_values && animation.values.size() == 1;  // any calcMode shows it
  if (!single_value && !animation.calc_mode.empty() && animation.calc_mode != "linear") {
    throw SvgError(str(where, " has calcMode=\"", animation.calc_mode,
                       "\"; motion at constant velocity between collisions needs calcMode=\"linear\" (the default, "
                       "so it can be left out): \"discrete\" jumps, \"paced\" ignores keyTimes and \"spline\" "
                       "accelerates"));
  }
  std::vector<double> values;
  auto number = [&](const std::string& item, const std::string& what) {
    try {
      return parse_length(item, what);
    } catch (const SvgError& error) {
      throw SvgError(str(where, ": ", error.what()));
    }
  };
  auto attribute = [&](const char* name) { return animation.attributes.at(name); };
  if (animation.has_values) {
    for (std::size_t i = 0; i < animation.values.size(); ++i) {
      values.push_back(number(animation.values[i], str("item ", i, " of values")));
    }
    if (values.empty()) throw SvgError(str(where, " has an empty values list"));
  } else if (animation.has("from") && animation.has("to")) {
    values = {number(attribute("from"), "from"), number(attribute("to"), "to")};
  } else if (animation.has("from") && animation.has("by")) {
    const double from = number(attribute("from"), "from");
    values = {from, from + number(attribute("by"), "by")};
  } else if (animation.has("to")) {
    values = {base, number(attribute("to"), "to")};
  } else if (animation.has("by")) {
    values = {base, base + number(attribute("by"), "by")};
  } else {
    throw SvgError(str(where, " has neither values=\"...\" nor from/to, so it animates nothing"));
  }
  if (values.size() == 1) return values[0];

  std::vector<double> times;
  if (animation.has_key_times) {
    for (std::size_t i = 0; i < animation.key_times.size(); ++i) {
      std::string_view item = animation.key_times[i];
      const auto value = take_number(item);
      if (!value || !trim(item).empty() || !std::isfinite(*value)) {
        throw SvgError(str(where, ": item ", i, " of keyTimes = \"", animation.key_times[i], "\" is not a number"));
      }
      times.push_back(*value);
    }
    if (times.size() != values.size()) {
      throw SvgError(str(where, " has ", values.size(), " values but ", times.size(),
                         " keyTimes; they must be equally many (one time per value), or browsers ignore the animation"));
    }
    if (std::abs(times.front()) > 1e-6 || std::abs(times.back() - 1) > 1e-6) {
      throw SvgError(str(where, ": keyTimes must start at 0 and end at 1 (fractions of dur), but go from ", times.front(),
                         " to ", times.back(), "; browsers ignore such an animation"));
    }
    for (std::size_t i = 1; i < times.size(); ++i) {
      if (times[i] < times[i - 1] - 1e-12) {
        throw SvgError(str(where, ": keyTimes must not decrease, but item ", i, " = ", times[i], " is smaller than item ",
                           i - 1, " = ", times[i - 1]));
      }
    }
  } else {
    for (std::size_t i = 0; i < values.size(); ++i) times.push_back(static_cast<double>(i) / static_cast<double>(values.size() - 1));
  }

  fraction = std::clamp(fraction, 0.0, 1.0);
  // The segment [times[i], times[i+1]] that holds `fraction`.
  const auto after = std::upper_bound(times.begin(), times.end(), fraction);
  std::size_t i = after == times.begin() ? 0 : static_cast<std::size_t>(after - times.begin()) - 1;
  i = std::min(i, times.size() - 2);
  const double span = times[i + 1] - times[i];
  if (!(span > 0)) return values[i + 1];
  const double s = std::clamp((fraction - times[i]) / span, 0.0, 1.0);
  return values[i] + s * (values[i + 1] - values[i]);
}

}  // namespace billiard::testing
