// Tests of the SVG reader the visualize_table and movie suites grade with: SVG written in every
// style a student (or their editor, or their browser's "save as") may use must be read as a
// browser reads it, and a file a browser refuses must be refused with the right line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "support/svg_reader.hpp"

namespace {

using billiard::testing::parse_svg;
using billiard::testing::read_svg;
using billiard::testing::sample_animation;
using billiard::testing::SvgCircle;
using billiard::testing::SvgDocument;
using billiard::testing::SvgError;

constexpr double kTolerance = 1e-9;

// The message parse_svg refuses `text` with, or a failure if it reads it.
std::string refusal(std::string_view text) {
  try {
    const SvgDocument document = parse_svg(text);
    ADD_FAILURE() << "the reader accepted a file a browser refuses (" << document.circles.size() << " circles):\n"
                  << text;
  } catch (const SvgError& error) {
    return error.what();
  }
  return "";
}

// Checks that `text` is refused at `line` with a message that contains `words`.
void expect_refused(std::string_view text, int line, std::string_view words) {
  const std::string message = refusal(text);
  const std::string prefix = "line " + std::to_string(line) + ": ";
  EXPECT_EQ(message.substr(0, prefix.size()), prefix) << "message: " << message;
  EXPECT_NE(message.find(words), std::string::npos) << "expected \"" << words << "\" in: " << message;
  EXPECT_EQ(SvgError(message).line(), line) << "message: " << message;  // the picture shows that line
}

TEST(SvgErrorLine, IsTheLineTheMessageNamesOrNone) {
  EXPECT_EQ(SvgError("movie.svg, line 7: <animate attributeName=\"cy\">: keyTimes must start at 0").line(), 7);
  EXPECT_EQ(SvgError("line 12: tag <circle> is not closed").line(), 12);
  EXPECT_EQ(SvgError("the file movie.svg is empty: nothing was written into it").line(), 0);
  EXPECT_EQ(SvgError("an inline 3: not a place").line(), 0);
  EXPECT_EQ(SvgError("line 99999999999999999999: too far").line(), 0);
}

void expect_circle(const SvgCircle& circle, double x, double y, double radius, int line) {
  EXPECT_NEAR(circle.x, x, kTolerance);
  EXPECT_NEAR(circle.y, y, kTolerance);
  EXPECT_NEAR(circle.radius, radius, kTolerance);
  EXPECT_EQ(circle.line, line);
}

// --- Valid files, in every style ---------------------------------------------------------------

TEST(SvgReader, DeclarationAndDoctype) {
  const SvgDocument document = parse_svg(R"svg(<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN"
  "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">
<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">
  <circle cx="10" cy="20" r="5"/>
</svg>
)svg");
  EXPECT_EQ(document.root_name, "svg");
  EXPECT_EQ(document.root_attributes.at("width"), "200");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 10, 20, 5, 5);
}

TEST(SvgReader, DoctypeWithAnInternalSubset) {
  // The subset's declarations hold '>' and "<circle" inside quotes: neither ends the DOCTYPE.
  const SvgDocument document = parse_svg(R"svg(<?xml version="1.0"?>
<!DOCTYPE svg [
  <!ENTITY decoy "<circle cx='99' r='99'/>">
  <!ATTLIST svg data-note CDATA "a > b">
]>
<svg xmlns="http://www.w3.org/2000/svg">
  <circle cx="1" cy="2" r="3"/>
</svg>)svg");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 1, 2, 3, 7);
}

TEST(SvgReader, CommentsMayHoldTagsAndSpanLines) {
  const SvgDocument document = parse_svg(R"svg(<!-- written by the course's visualize_table -->
<svg xmlns="http://www.w3.org/2000/svg">
  <!-- <circle cx="100" cy="100" r="100"/> was the old table
       <circle cx="5" r="1"/>
  -->
  <circle cx="1" cy="1" r="1"/>
  <!--<circle r="2"/>--><circle cx="2" cy="2" r="2"/>
</svg>
<!-- <circle cx="3"/> after the root is allowed: it is a comment -->
)svg");
  ASSERT_EQ(document.circles.size(), 2u);
  expect_circle(document.circles[0], 1, 1, 1, 6);
  expect_circle(document.circles[1], 2, 2, 2, 7);
}

TEST(SvgReader, CdataSectionsAreText) {
  const SvgDocument document = parse_svg(R"svg(<svg xmlns="http://www.w3.org/2000/svg">
  <style><![CDATA[
    circle { fill: red; }  /* <circle cx="9" r="9"/> */
  ]]></style>
  <script><![CDATA[ if (a < b && b > c) document.write('<circle r="8"/>'); ]]></script>
  <circle cx="4" cy="5" r="6"/>
</svg>)svg");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 4, 5, 6, 6);
}

TEST(SvgReader, EntitiesInAttributeValuesAreDecoded) {
  const SvgDocument document = parse_svg(
      "<svg xmlns=\"http://www.w3.org/2000/svg\">\n"
      "<circle id=\"a &amp; b &lt;c&gt; &quot;q&quot; &apos;s&apos;\" cx=\"&#49;&#x32;\" cy=\"&#45;3\" r=\"&#x34;\"/>\n"
      "</svg>");
  ASSERT_EQ(document.circles.size(), 1u);
  EXPECT_EQ(document.circles[0].attributes.at("id"), "a & b <c> \"q\" 's'");
  expect_circle(document.circles[0], 12, -3, 4, 2);
}

TEST(SvgReader, NamespacePrefixes) {
  const SvgDocument document = parse_svg(R"svg(<svg:svg xmlns:svg="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
  <svg:g transform="translate(5 5)">
    <svg:circle cx="1" cy="2" r="3">
      <svg:animate attributeName="cx" values="1;11" dur="2s"/>
    </svg:circle>
  </svg:g>
</svg:svg>)svg");
  EXPECT_EQ(document.root_name, "svg");
  EXPECT_EQ(document.root_attributes.at("xmlns:svg"), "http://www.w3.org/2000/svg");
  ASSERT_EQ(document.circles.size(), 1u);
  const SvgCircle& circle = document.circles[0];
  expect_circle(circle, 6, 7, 3, 3);
  EXPECT_EQ(circle.ancestors, (std::vector<std::string>{"svg", "g"}));
  ASSERT_EQ(circle.animations.size(), 1u);
  EXPECT_EQ(circle.animations[0].attribute_name, "cx");
  EXPECT_EQ(circle.animations[0].line, 4);
}

TEST(SvgReader, DefaultNamespace) {
  const SvgDocument document = parse_svg(
      R"svg(<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"><circle cx="7" cy="8" r="9"/></svg>)svg");
  EXPECT_EQ(document.root_attributes.at("xmlns"), "http://www.w3.org/2000/svg");
  EXPECT_EQ(document.root_attributes.at("xmlns:xlink"), "http://www.w3.org/1999/xlink");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 7, 8, 9, 1);
}

TEST(SvgReader, NestedGroupTransformsComposeFromTheRootDown) {
  const SvgDocument document = parse_svg(R"svg(<svg xmlns="http://www.w3.org/2000/svg">
  <g transform="translate(100, 0)">
    <g transform="scale(2)">
      <circle cx="10" cy="5" r="3" transform="rotate(90)"/>
    </g>
    <circle cx="1" cy="1" r="1"/>
  </g>
  <circle cx="1" cy="1" r="1"/>
</svg>)svg");
  ASSERT_EQ(document.circles.size(), 3u);
  // rotate(90) takes (10, 5) to (-5, 10); scale(2) to (-10, 20); translate to (90, 20).
  expect_circle(document.circles[0], 90, 20, 6, 4);
  EXPECT_EQ(document.circles[0].ancestors, (std::vector<std::string>{"svg", "g", "g"}));
  expect_circle(document.circles[1], 101, 1, 1, 6);  // only the outer group's translation
  expect_circle(document.circles[2], 1, 1, 1, 8);    // none
}

TEST(SvgReader, SingleAndDoubleQuotes) {
  const SvgDocument document = parse_svg(
      "<svg xmlns='http://www.w3.org/2000/svg'>\n"
      "<circle cx='10' cy=\"20\" r = '5' id='say \"hi\"' class=\"it's\"/>\n"
      "</svg>");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 10, 20, 5, 2);
  EXPECT_EQ(document.circles[0].attributes.at("id"), "say \"hi\"");
  EXPECT_EQ(document.circles[0].attributes.at("class"), "it's");
}

TEST(SvgReader, AttributesOverSeveralLinesGiveTheTagsLine) {
  const SvgDocument document = parse_svg(
      "<svg xmlns=\"http://www.w3.org/2000/svg\">\n\n"
      "  <circle\n"
      "     cx=\"1\"\n"
      "     cy=\"2\"\n"
      "     r=\"3\" />\n"
      "</svg>\n");
  ASSERT_EQ(document.circles.size(), 1u);
  expect_circle(document.circles[0], 1, 2, 3, 3);
}

TEST(SvgReader, WindowsLineEndingsAndByteOrderMark) {
  const SvgDocument document = parse_svg(
      "\xEF\xBB\xBF<?xml version=\"1.0\"?>\r\n<svg xmlns=\"http://www.w3.org/2000/svg\">\r\n"
      "<circle cx=\"1\" cy=\"2\" r=\"3\"/>\r\n\r\n<circle cx=\"4\" cy=\"5\" r=\"6\"/>\r\n</svg>\r\n");
  ASSERT_EQ(document.circles.size(), 2u);
  expect_circle(document.circles[0], 1, 2, 3, 3);
  expect_circle(document.circles[1], 4, 5, 6, 5);
}

// A student's file after a round trip through Inkscape (or a browser's "save as" of it): XML
// declaration with standalone, many namespaces, metadata, sodipodi:namedview, a layer group with
// a translation, styles, units on the root.
TEST(SvgReader, InkscapeStyleFile) {
  const SvgDocument document = parse_svg(R"svg(<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!-- Created with Inkscape (http://www.inkscape.org/) -->

<svg
   width="210mm"
   height="297mm"
   viewBox="0 0 210 297"
   version="1.1"
   id="svg5"
   inkscape:version="1.2.2"
   sodipodi:docname="table.svg"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   xmlns="http://www.w3.org/2000/svg"
   xmlns:svg="http://www.w3.org/2000/svg"
   xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"
   xmlns:cc="http://creativecommons.org/ns#"
   xmlns:dc="http://purl.org/dc/elements/1.1/">
  <sodipodi:namedview
     id="namedview7"
     pagecolor="#ffffff"
     bordercolor="#666666"
     inkscape:zoom="0.73"
     inkscape:current-layer="layer1" />
  <defs
     id="defs2">
    <circle id="marker-dot" cx="0" cy="0" r="0.5" style="fill:#000000" />
  </defs>
  <metadata
     id="metadata1">
    <rdf:RDF>
      <cc:Work
         rdf:about="">
        <dc:format>image/svg+xml</dc:format>
        <dc:title>Billiard &amp; friends</dc:title>
      </cc:Work>
    </rdf:RDF>
  </metadata>
  <g
     inkscape:label="Layer 1"
     inkscape:groupmode="layer"
     id="layer1"
     transform="translate(105,148.5)">
    <circle
       style="fill:#e6f2e6;stroke:#2e7d32;stroke-width:0.2"
       id="table"
       cx="0"
       cy="0"
       r="100" />
    <circle
       style="fill:#1565c0;fill-opacity:1;stroke:none"
       id="circle1"
       cx="-12.5"
       cy="30.25"
       r="4" />
  </g>
</svg>
)svg");
  EXPECT_EQ(document.root_attributes.at("width"), "210mm");
  ASSERT_EQ(document.circles.size(), 3u);
  EXPECT_FALSE(document.circles[0].rendered);  // inside <defs>
  const auto rendered = document.rendered_circles();
  ASSERT_EQ(rendered.size(), 2u);
  expect_circle(*rendered[0], 105, 148.5, 100, 44);
  expect_circle(*rendered[1], 92.5, 178.75, 4, 50);
  EXPECT_EQ(rendered[1]->attributes.at("style"), "fill:#1565c0;fill-opacity:1;stroke:none");
  EXPECT_EQ(rendered[1]->ancestors, (std::vector<std::string>{"svg", "g"}));
}

// As a browser's "save as" or a pretty-printer writes it: processing instructions (a style
// sheet), tabs, a comment between the attributes' lines, empty elements written open and close.
TEST(SvgReader, ProcessingInstructionsAndOpenCloseElements) {
  const SvgDocument document = parse_svg(
      "<?xml version='1.0' encoding='utf-8'?>\n"
      "<?xml-stylesheet type=\"text/css\" href=\"table.css\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\">\n"
      "\t<title>A table &lt;3 discs&gt;</title>\n"
      "\t<circle\tcx=\"3\"\tcy=\"4\"\tr=\"5\"></circle>\n"
      "\t<circle cx=\"1\" cy=\"1\" r=\"1\"><!-- no animation --></circle>\n"
      "</svg>\n");
  ASSERT_EQ(document.circles.size(), 2u);
  expect_circle(document.circles[0], 3, 4, 5, 5);
  expect_circle(document.circles[1], 1, 1, 1, 6);
}

TEST(SvgReader, AnimationsOfCircles) {
  const SvgDocument document = parse_svg(R"svg(<svg xmlns="http://www.w3.org/2000/svg">
  <circle cx="0" cy="0" r="1">
    <animate attributeName="cx" values="0; 10; 30" keyTimes="0;0.5;1" dur="4s" repeatCount="indefinite"/>
    <animate attributeName="cy" from="0" to="8" dur="4000ms"/>
  </circle>
  <g><animate attributeName="opacity" values="0;1" dur="1s"/></g>
</svg>)svg");
  ASSERT_EQ(document.circles.size(), 1u);
  const SvgCircle& circle = document.circles[0];
  ASSERT_EQ(circle.animations.size(), 2u);  // the group's <animate> belongs to no circle
  const auto& cx = *circle.animations_of("cx").at(0);
  EXPECT_EQ(cx.line, 3);
  EXPECT_EQ(cx.values, (std::vector<std::string>{"0", "10", "30"}));
  EXPECT_NEAR(cx.dur_seconds(), 4, kTolerance);
  EXPECT_NEAR(sample_animation(cx, 0.75, 0), 20, kTolerance);
  const auto& cy = *circle.animations_of("cy").at(0);
  EXPECT_EQ(cy.line, 4);
  EXPECT_NEAR(cy.dur_seconds(), 4, kTolerance);
  EXPECT_NEAR(sample_animation(cy, 0.25, 0), 2, kTolerance);
}

TEST(SvgReader, LineNumbersFarDown) {
  std::string text = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n";
  for (int i = 0; i < 998; ++i) text += "<circle cx=\"" + std::to_string(i) + "\" cy=\"0\" r=\"1\"/>\n";
  text += "</svg>\n";
  const SvgDocument document = parse_svg(text);
  ASSERT_EQ(document.circles.size(), 998u);
  expect_circle(document.circles[997], 997, 0, 1, 999);
  expect_refused(text + "<svg/>\n", 1001, "a second top-level element <svg>");
}

TEST(SvgReader, UnreadableTransformCountsOnlyAboveACircle) {
  // A browser would skip the transform; the reader cannot place circles under it, so it says so.
  const SvgDocument document = parse_svg(
      "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g transform=\"perspective(3)\"/>\n"
      "<circle cx=\"1\" cy=\"1\" r=\"1\"/>\n</svg>");
  EXPECT_EQ(document.circles.size(), 1u);
  expect_refused(
      "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g transform=\"perspective(3)\">\n"
      "<circle cx=\"1\" cy=\"1\" r=\"1\"/>\n</g>\n</svg>",
      2, "perspective(...)");
}

// --- Files a browser refuses ---------------------------------------------------------------------

TEST(SvgReaderRefuses, MismatchedEndTag) {
  expect_refused("<svg>\n<g>\n<circle r=\"1\">\n</g>\n</svg>", 4, "</g> closes <circle> (opened on line 3)");
}

TEST(SvgReaderRefuses, MismatchedEndTagAfterAClosedChild) {
  // The last element read (the circle) is closed already: the open one is its parent.
  expect_refused("<svg>\n<g>\n<circle r=\"1\"/></h>\n</svg>", 3, "</h> closes <g> (opened on line 2)");
  expect_refused("<svg>\n<g><circle r=\"1\"></circle></g>\n</x>", 3, "</x> closes <svg> (opened on line 1)");
  expect_refused("<svg>\n<g>\n<g>\n</g>\n</svg>\n", 5, "</svg> closes <g> (opened on line 2)");
}

TEST(SvgReaderRefuses, MismatchBelowManyClosedElementsStillHasItsLine) {
  // The open element is searched for from the deepest up, a few levels only: beyond them the
  // message does not guess which element is open, but it still gives the line.
  std::string text = "<svg>\n";
  for (int i = 0; i < 40; ++i) text += "<g>";
  for (int i = 0; i < 40; ++i) text += "</g>";
  text += "\n</h>\n";
  expect_refused(text, 3, "start and end tags do not match here");
}

TEST(SvgReaderRefuses, PrefixedEndTagMustMatchExactly) {
  expect_refused("<svg:svg xmlns:svg=\"http://www.w3.org/2000/svg\">\n<svg:circle r=\"1\"></circle>\n</svg:svg>", 2,
                 "</circle> closes <svg:circle> (opened on line 2)");
}

TEST(SvgReaderRefuses, ElementNeverClosed) {
  expect_refused("<svg>\n<g>\n<circle r=\"1\"/>\n", 2, "<g> is never closed");
  expect_refused("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<circle r=\"1\"/>\n", 1, "<svg> is never closed");
  // The file ends inside the end tag.
  expect_refused("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<circle r=\"1\"/>\n</sv", 1, "<svg> is never closed");
}

TEST(SvgReaderRefuses, FileEndsInsideATag) {
  expect_refused("<svg>\n<circle r=\"1\"/>\n<circle cx=\"1\"\n  r=\"2\"", 3, "the tag <circle is never closed");
  expect_refused("<svg>\n<circle r=\"1\"/>\n<circle cx=\"1\"\n  r=\"2", 4, "the file ends inside it");
}

TEST(SvgReaderRefuses, EndTagWithoutStartTag) {
  expect_refused("<svg>\n</svg>\n</g>\n", 3, "</g> has no matching <g>");
}

TEST(SvgReaderRefuses, TextOutsideTheRoot) {
  expect_refused("<svg>\n</svg>\n\n  appended text\n", 4, "text \"appended text\" outside the <svg> element");
  expect_refused("<?xml version=\"1.0\"?>\nWidth: 10\n<svg>\n</svg>\n", 2, "may come before <svg>");
  // A single character at the very end is still text.
  expect_refused("<svg>\n</svg>\nx", 3, "text \"x\"");
  expect_refused("<svg>\n</svg>\n&amp;", 3, "outside the <svg> element");
}

TEST(SvgReaderRefuses, CdataOutsideTheRoot) {
  expect_refused("<svg>\n</svg>\n<![CDATA[ <circle r=\"1\"/> ]]>\n", 3, "a CDATA section outside the <svg> element");
}

TEST(SvgReaderRefuses, SecondTopLevelElement) {
  expect_refused("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<circle r=\"1\"/>\n</svg>\n<svg>\n</svg>\n", 4,
                 "a second top-level element <svg> after </svg>");
}

TEST(SvgReaderRefuses, DuplicateAttribute) {
  expect_refused("<svg>\n<circle cx=\"1\"\n  r=\"1\"\n  cx=\"2\"/>\n</svg>", 4, "<circle> has the attribute cx twice");
  expect_refused("<svg width=\"1\" width='2'>\n</svg>", 1, "<svg> has the attribute width twice");
  // Duplicates anywhere, also in elements the reader otherwise ignores.
  expect_refused("<svg>\n<metadata>\n<dc:title xml:lang=\"en\" xml:lang=\"fr\"/>\n</metadata>\n</svg>", 3,
                 "the attribute xml:lang twice");
}

TEST(SvgReaderRefuses, UnquotedOrMissingAttributeValues) {
  expect_refused("<svg>\n<circle cx=\"1\"\n r=5/>\n</svg>", 3, "the value of r must be in quotes");
  expect_refused("<svg>\n<circle r\n cx=\"1\"/>\n</svg>", 2, "the attribute r has no value");
  expect_refused("<svg>\n<circle id='one\"/>\n</svg>", 2, "the value of id is never closed with the '");
  expect_refused("<svg>\n<circle r=\"1\"cx=\"2\"/>\n</svg>", 2, "attributes must be separated by a space");
}

TEST(SvgReaderRefuses, BadTags) {
  expect_refused("<svg>\n<text>1 < 2</text>\n</svg>", 2, "a literal < in text must be written &lt;");
  expect_refused("<svg>\n<circle r=\"1\" / >\n</svg>", 2, "'/' must be directly followed by '>'");
  expect_refused("<svg>\n</svg foo=\"1\">", 2, "end tags have no attributes");
  expect_refused("<svg>\n<!-- never closed\n<circle r=\"1\"/>\n</svg>", 2, "a comment <!-- is never closed");
  expect_refused("<svg>\n<style><![CDATA[ circle {}\n</style>\n</svg>", 2, "never closed with ]]>");
}

TEST(SvgReaderRefuses, NulCharacter) {
  using namespace std::string_literals;
  expect_refused("<svg>\n<circle r=\"1\"/>\n\0\n</svg>"s, 3, "NUL character");
}

TEST(SvgReaderRefuses, NotAnSvgFile) {
  expect_refused("<?xml version=\"1.0\"?>\n<html>\n</html>", 2, "the file's top-level element is <html>");
  for (const char* text : {"", "   \n", "<!-- only a comment -->\n", "<?xml version=\"1.0\"?>\n"}) {
    EXPECT_NE(refusal(text).find("the file contains no element at all"), std::string::npos) << "for: " << text;
  }
}

TEST(SvgReaderRefuses, ReadSvgNamesTheFile) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("svg_reader_tests_" + std::to_string(getpid()) + ".svg");
  std::ofstream(file) << "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<circle r=\"1\">\n</svg>\n";
  try {
    read_svg(file);
    ADD_FAILURE() << "read_svg accepted a file with an unclosed <circle>";
  } catch (const SvgError& error) {
    const std::string message = error.what();
    const std::string name = file.filename().string();
    EXPECT_EQ(message.rfind(name + ", line 3: </svg> closes <circle> (opened on line 2)", 0), 0u) << message;
  }
  std::filesystem::remove(file);
}

}  // namespace
