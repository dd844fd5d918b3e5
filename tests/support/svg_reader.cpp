#include "support/svg_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>
#include <utility>

#include <pugixml.hpp>

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

// --- The XML layer -------------------------------------------------------------------------------
// pugixml reads the XML. What it tolerates but XML (and so a browser) refuses is checked here,
// and its errors, a status and a byte offset, become messages with line numbers.

// Every kind of node is kept (parse_full), and with parse_fragment also text outside the root
// element, which pugixml would otherwise drop without a word. Whitespace-only text is not kept:
// it is allowed anywhere.
constexpr unsigned kParseOptions = pugi::parse_full | pugi::parse_fragment;

// Line numbers (from 1) of byte offsets in the text.
class Lines {
 public:
  explicit Lines(std::string_view text) {
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '\n') newlines_.push_back(i);
    }
  }
  int at(std::ptrdiff_t offset) const {
    const std::size_t position = offset < 0 ? 0 : static_cast<std::size_t>(offset);
    return static_cast<int>(std::lower_bound(newlines_.begin(), newlines_.end(), position) - newlines_.begin()) + 1;
  }
  // Line of an element's tag, a comment, ... (pugixml's offset of its name or value).
  int of(const pugi::xml_node& node) const { return at(node.offset_debug()); }

 private:
  std::vector<std::size_t> newlines_;
};

// A text parsed by pugixml. It parses a copy in place, so the names and values of nodes and
// attributes point into that copy, and an attribute's offset is where its name is. The copy ends
// with a NUL: in place, pugixml otherwise takes over the last byte as the end mark, and text at the
// very end (after the root element) would lose its last character.
struct Xml {
  explicit Xml(std::string_view text) : buffer(text.begin(), text.end()) {
    buffer.push_back('\0');
    // UTF-8 as written: no conversion, so that offsets are those of the file's bytes.
    result = document.load_buffer_inplace(buffer.data(), buffer.size(), kParseOptions, pugi::encoding_utf8);
  }
  Xml(const Xml&) = delete;
  Xml& operator=(const Xml&) = delete;

  // Offset in the text of a name or value that points into the copy; -1 for any other string.
  std::ptrdiff_t offset_of(const char* name) const {
    const char* begin = buffer.data();
    const std::less<const char*> before;  // defined for any two pointers, unlike <
    return !before(name, begin) && before(name, begin + buffer.size()) ? name - begin : -1;
  }

  std::vector<char> buffer;
  pugi::xml_document document;
  pugi::xml_parse_result result;
};

bool starts_name(char ch) {
  return std::isalpha(static_cast<unsigned char>(ch)) || ch == '_' || ch == ':' ||
         static_cast<unsigned char>(ch) >= 0x80;
}

// The name written at `offset` (up to a space, '>', '/', '<' or the end), e.g. in an end tag.
std::string name_at(std::string_view text, std::size_t offset) {
  const std::size_t start = std::min(offset, text.size());
  std::size_t end = start;
  while (end < text.size() && !is_space(text[end]) && text[end] != '>' && text[end] != '/' && text[end] != '<') ++end;
  return std::string(text.substr(start, end - start));
}

// Pre-order walk of the elements from `root` (itself included) without recursion, as a file may
// nest deeply: visit(element, depth), depth 0 for `root`.
template <typename Visit>
void for_each_element(const pugi::xml_node& root, Visit visit) {
  pugi::xml_node node = root;
  int depth = 0;
  for (;;) {
    if (node.type() == pugi::node_element) {
      visit(node, depth);
      if (pugi::xml_node child = node.first_child()) {
        node = child;
        ++depth;
        continue;
      }
    }
    while (node != root && !node.next_sibling()) {
      node = node.parent();
      --depth;
    }
    if (node == root) return;
    node = node.next_sibling();
  }
}

// The element that was open when the parse stopped. pugixml keeps the tree it built up to an
// error; the open elements are the last child at each level, from the top down, but the deepest
// of those may be closed already. The open one is the element whose end tag, and its ancestors',
// make the text before the error well-formed. An empty node if no element is open; nullopt if it
// is not found within a few tries (each parses the text again; in practice the open element is
// the deepest or close to it).
std::optional<pugi::xml_node> innermost_open(std::string_view before, const pugi::xml_document& partial) {
  constexpr std::size_t kMaxTries = 32;
  std::vector<pugi::xml_node> chain;
  for (pugi::xml_node node = partial.last_child(); node.type() == pugi::node_element; node = node.last_child()) {
    chain.push_back(node);
  }
  const std::size_t shallowest = chain.size() > kMaxTries ? chain.size() - kMaxTries : 0;
  for (std::size_t depth = chain.size(); depth-- > shallowest;) {
    std::string closed(before);
    for (std::size_t i = depth + 1; i-- > 0;) closed += str("</", chain[i].name(), ">");
    if (Xml(closed).result) return chain[depth];
  }
  if (shallowest > 0) return std::nullopt;
  return pugi::xml_node();
}

// The deepest last node of the partial tree: the one pugixml was reading when it stopped.
pugi::xml_node last_read(const pugi::xml_document& partial) {
  pugi::xml_node node = partial.last_child();
  while (node.last_child()) node = node.last_child();
  return node;
}

// Turns pugixml's error into a message for a student.
[[noreturn]] void refuse_malformed(std::string_view text, const Lines& lines, const Xml& xml) {
  const std::size_t at =
      std::min(static_cast<std::size_t>(std::max<std::ptrdiff_t>(xml.result.offset, 0)), text.size());
  const int line = lines.at(static_cast<std::ptrdiff_t>(at));
  const pugi::xml_node last = last_read(xml.document);
  const std::string element = last.type() == pugi::node_element ? last.name() : "";
  const std::string in_tag = last.type() == pugi::node_declaration ? std::string("in the declaration <?xml ...?>")
                             : element.empty()                     ? std::string("in a tag")
                                                                   : str("in <", element, ">");
  auto skip_spaces = [&text](std::size_t pos) {
    while (pos < text.size() && is_space(text[pos])) ++pos;
    return pos;
  };
  switch (xml.result.status) {
    case pugi::status_unrecognized_tag:
      fail_at(line,
              "'<' is not followed by an element name, <!-- (a comment) or <? (a processing instruction); "
              "a literal < in text must be written &lt;");
    case pugi::status_bad_pi:
      fail_at(line,
              "a processing instruction <?...?> (such as the <?xml ...?> declaration) has no name right "
              "after <? or is never closed with ?>");
    case pugi::status_bad_comment:
      fail_at(line, "a comment <!-- is never closed with -->");
    case pugi::status_bad_cdata:
      fail_at(line, "a CDATA section is misspelt (it is written <![CDATA[ ... ]]>) or never closed with ]]>");
    case pugi::status_bad_doctype:
      fail_at(line,
              "a declaration <!DOCTYPE ...> is malformed or never closed with >; it may only come before "
              "the <svg> element");
    case pugi::status_bad_start_element:
      if (text.find('>', at) == std::string_view::npos) {
        fail_at(last ? lines.of(last) : line,
                str("the tag <", element, " is never closed with > or />: the file ends inside it ",
                    "(did the program stop writing early, or forget to close the file?)"));
      }
      if ((at > 0 && text[at - 1] == '/') || (at < text.size() && text[at] == '/')) {
        fail_at(line, str(in_tag, ": '/' must be directly followed by '>' (an element without children is written <",
                          element, " ... />)"));
      }
      fail_at(line, str(in_tag, ": unexpected character '", at < text.size() ? text[at] : ' ',
                        "'; attribute names start with a letter, and a tag ends with > or />"));
    case pugi::status_bad_attribute: {
      const pugi::xml_attribute attribute = last.last_attribute();
      const std::ptrdiff_t name_offset = attribute ? xml.offset_of(attribute.name()) : -1;
      if (name_offset < 0) fail_at(line, str(in_tag, ": cannot read an attribute; write them as name=\"value\""));
      const std::string name = attribute.name();
      const int attribute_line = lines.at(name_offset);
      std::size_t pos = skip_spaces(static_cast<std::size_t>(name_offset) + name.size());
      if (pos >= text.size() || text[pos] != '=') {
        fail_at(attribute_line, str(in_tag, ": the attribute ", name, " has no value (write ", name, "=\"...\")"));
      }
      pos = skip_spaces(pos + 1);
      if (pos >= text.size() || (text[pos] != '"' && text[pos] != '\'')) {
        fail_at(attribute_line, str(in_tag, ": the value of ", name, " must be in quotes, e.g. ", name, "=\"12.5\""));
      }
      const char quote = text[pos];
      if (text.find(quote, pos + 1) == std::string_view::npos) {
        fail_at(attribute_line,
                str(in_tag, ": the value of ", name, " is never closed with the ", quote, " that opens it",
                    text.find('>', pos) == std::string_view::npos
                        ? ": the file ends inside it (did the program stop writing early?)"
                        : ""));
      }
      // The value is complete: what follows it is wrong.
      if (at < text.size() && starts_name(text[at])) {
        fail_at(line, str(in_tag, ": attributes must be separated by a space, but the value of ", name,
                          " is directly followed by ", name_at(text, at).substr(0, 40)));
      }
      fail_at(line, str(in_tag, ": unexpected character '", at < text.size() ? text[at] : ' ', "' after the value of ",
                        name, "; a tag ends with > or />"));
    }
    case pugi::status_bad_end_element: {
      const std::size_t open = text.rfind("</", at);
      const std::string name = open == std::string_view::npos ? std::string() : name_at(text, open + 2);
      if (text.find('>', at) == std::string_view::npos)
        fail_at(line, str("the end tag </", name, " is never closed with >"));
      fail_at(line,
              str("the end tag </", name, " must be closed with > right after the name (end tags have no attributes)"));
    }
    case pugi::status_end_element_mismatch: {
      // pugixml stops at the name of an end tag that does not match, or at the end of the file.
      const bool end_tag = at >= 2 && text.substr(at - 2, 2) == "</";
      // A file that ends inside that end tag ("</sv") is cut short, whatever the name says.
      const bool cut_short = !end_tag || text.find('>', at) == std::string_view::npos;
      auto open = innermost_open(text.substr(0, end_tag ? at - 2 : text.size()), xml.document);
      if (!end_tag && open && !*open) {
        // The file ends inside a tag ("</sv"): what was open before it.
        const std::size_t last_tag = text.rfind('<');
        if (last_tag != std::string_view::npos) open = innermost_open(text.substr(0, last_tag), xml.document);
      }
      if (!cut_short && open) {
        const std::string name = name_at(text, at);
        if (!*open) {
          const pugi::xml_node closed_root =
              xml.document.find_child([](const pugi::xml_node& node) { return node.type() == pugi::node_element; });
          fail_at(line, str("</", name, "> has no matching <", name, "> before it",
                            closed_root ? str(" (<", closed_root.name(), "> was closed before it)") : ""));
        }
        fail_at(line, str("</", name, "> closes <", open->name(), "> (opened on line ", lines.of(*open),
                          "): tags must be closed in the reverse order they were opened, and an element without "
                          "children is written <",
                          open->name(), " ... />"));
      }
      if (cut_short && open && *open) {
        fail_at(lines.of(*open), str("<", open->name(), "> is never closed: the file ends before its </", open->name(),
                                     "> (did the program stop writing early, or forget to close the file?)"));
      }
      fail_at(line,
              "start and end tags do not match here: each <name ...> needs its </name>, closed in the reverse "
              "order of opening (or written <name ... /> without children)");
    }
    default:
      fail_at(line, str("the XML reader cannot read the file here: ", xml.result.description()));
  }
}

// Checks what pugixml accepts but a browser refuses (text, CDATA or a second element outside the
// root, an attribute written twice); returns the root element.
pugi::xml_node check_well_formed(std::string_view text, const Lines& lines, const Xml& xml) {
  pugi::xml_node root;
  for (pugi::xml_node node : xml.document.children()) {
    switch (node.type()) {
      case pugi::node_element:
        if (root) {
          fail_at(lines.of(node),
                  str("a second top-level element <", node.name(), "> after </", root.name(),
                      ">: a file holds one picture (was the file appended to instead of overwritten?)"));
        }
        root = node;
        break;
      case pugi::node_pcdata: {
        const std::string_view content = trim(node.value());
        if (content.empty()) break;
        std::size_t first = static_cast<std::size_t>(std::max<std::ptrdiff_t>(node.offset_debug(), 0));
        while (first < text.size() && is_space(text[first])) ++first;
        fail_at(
            lines.at(static_cast<std::ptrdiff_t>(first)),
            str("text \"", content.substr(0, 40), content.size() > 40 ? "..." : "", "\" outside the <svg> element: ",
                root ? "nothing but comments may follow </svg> (was the file appended to instead of overwritten?)"
                     : "nothing but <?xml ...?>, <!DOCTYPE ...> and comments may come before <svg>"));
      }
      case pugi::node_cdata:
        fail_at(lines.of(node), "a CDATA section outside the <svg> element");
      default:
        break;  // the declaration, DOCTYPE, comments, processing instructions
    }
  }
  if (!root) {
    throw SvgError(
        "the file contains no element at all (it is empty or only has comments); expected <svg ...> ... </svg>");
  }
  for_each_element(root, [&](const pugi::xml_node& element, int) {
    std::set<std::string_view> names;
    for (const pugi::xml_attribute& attribute : element.attributes()) {
      if (names.insert(attribute.name()).second) continue;
      const std::ptrdiff_t offset = xml.offset_of(attribute.name());
      fail_at(offset >= 0 ? lines.at(offset) : lines.of(element),
              str("<", element.name(), "> has the attribute ", attribute.name(),
                  " twice; a browser refuses the whole file, so write each attribute once"));
    }
  });
  return root;
}

// --- The SVG layer -------------------------------------------------------------------------------

// What the walk knows of an element and its ancestors.
struct Frame {
  std::string name;  // local name
  Affine transform;
  std::string transform_error;  // set if this element or an ancestor has a transform we cannot read
  bool hidden = false;
  int circle = -1;  // index into the document's circles if this element is a circle
};

// The circles under `root`, with their transforms and animations.
SvgDocument read_circles(const pugi::xml_node& root, const Lines& lines) {
  SvgDocument document;
  document.root_name = local_name(root.name());
  if (document.root_name != "svg") {
    fail_at(lines.of(root),
            str("the file's top-level element is <", root.name(), ">; an SVG file's must be <svg ...>"));
  }
  std::vector<Frame> ancestors;
  for_each_element(root, [&](const pugi::xml_node& element, int depth) {
    ancestors.resize(static_cast<std::size_t>(depth));
    const int tag_line = lines.of(element);
    std::map<std::string, std::string> attributes;
    for (const pugi::xml_attribute& attribute : element.attributes())
      attributes.emplace(attribute.name(), attribute.value());

    Frame frame;
    frame.name = local_name(element.name());
    if (ancestors.empty()) {
      document.root_attributes = attributes;
    } else {
      const Frame& parent = ancestors.back();
      frame.transform = parent.transform;
      frame.transform_error = parent.transform_error;
      frame.hidden = parent.hidden;
      if (frame.name == "svg" && frame.transform_error.empty()) {
        frame.transform_error =
            str("line ", tag_line,
                ": an <svg> inside <svg> starts a new viewport, which the test reader does not understand; "
                "draw everything in one <svg> and use <g transform=\"...\"> to move or scale");
      }
    }
    if (hides_children(frame.name)) frame.hidden = true;
    if (const auto it = attributes.find("transform"); it != attributes.end() && frame.transform_error.empty()) {
      Affine own;
      const std::string error = parse_transform(it->second, own);
      if (error.empty()) {
        frame.transform = frame.transform.then_inner(own);
      } else {
        frame.transform_error = str("line ", tag_line, ": ", error);
      }
    }

    if (frame.name == "circle") {
      if (!frame.transform_error.empty()) throw SvgError(frame.transform_error);
      SvgCircle circle;
      circle.line = tag_line;
      for (const Frame& ancestor : ancestors) circle.ancestors.push_back(ancestor.name);
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
      frame.circle = static_cast<int>(document.circles.size());
      document.circles.push_back(std::move(circle));
    } else if (frame.name == "animate" && !ancestors.empty() && ancestors.back().circle >= 0) {
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
      document.circles[static_cast<std::size_t>(ancestors.back().circle)].animations.push_back(std::move(animation));
    }
    ancestors.push_back(std::move(frame));
  });
  return document;
}

// Refuses what pugixml cannot say with a line number: a file that is not UTF-8 (or ASCII).
void check_encoding(std::string_view text, const Lines& lines) {
  if (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF") {
    throw SvgError(
        "the file is written in UTF-16 (it starts with a UTF-16 byte order mark); write it as UTF-8 or "
        "plain ASCII, as std::ofstream does with char strings");
  }
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    fail_at(lines.at(static_cast<std::ptrdiff_t>(nul)),
            "the file contains a NUL character (byte 0), which XML does not allow; was a '\\0' or binary data "
            "written into it?");
  }
}
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

SvgDocument parse_svg(std::string_view text) {
  const Lines lines(text);
  check_encoding(text, lines);
  const Xml xml(text);
  if (!xml.result) refuse_malformed(text, lines, xml);
  SvgDocument document = read_circles(check_well_formed(text, lines, xml), lines);
  document.text = std::string(text);
  return document;
}

int SvgError::line() const {
  const std::string_view message = what();
  for (std::size_t at = message.find("line "); at != std::string_view::npos; at = message.find("line ", at + 1)) {
    if (at != 0 && (at < 2 || message.substr(at - 2, 2) != ", ")) continue;  // "line N:" starts it or a clause
    std::size_t end = at + 5;
    while (end < message.size() && message[end] >= '0' && message[end] <= '9') ++end;
    if (end > at + 5 && end <= at + 14 && end < message.size() && message[end] == ':') {
      return std::stoi(std::string(message.substr(at + 5, end - at - 5)));
    }
  }
  return 0;
}

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
