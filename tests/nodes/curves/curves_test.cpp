#include "nodes/curves/curves.h"

#include <gtest/gtest.h>

#include <cmath>

#include "nodes/core/errors.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::string svg(const std::string& body) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\">" + body + "</svg>";
}

std::string error_of(const std::string& text) {
  try {
    parse_svg(text, "drawing.svg");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

// Quadratic Bezier (0,0) (1,2) (2,0): length = (sqrt(20) + ln((4 + sqrt(20)) / 2)) / 2, in closed form.
const double kQuadLength = 0.5 * (std::sqrt(20.0) + std::log((4 + std::sqrt(20.0)) / 2));

TEST(ParseSvg, QuadraticAndCubicBezierHaveTheirArcLength) {
  // The cubic is the quadratic degree-elevated: control points P0 + 2/3 (P1 - P0) and P2 + 2/3 (P1 - P2).
  for (const std::string d : {"M0 0 Q1 2 2 0", "m0,0 q1,2 2,0",
                              "M0 0 C0.666666666667 1.333333333333 "
                              "1.333333333333 1.333333333333 2 0",
                              "M0 0c.666666666667 1.333333333333 1.333333333333 1.333333333333 2 0"}) {
    const Curves c = parse_svg(svg("<path d=\"" + d + "\"/>"), "q.svg");
    ASSERT_EQ(c.size(), 1u) << d;
    EXPECT_NEAR(curve_length(c[0]), kQuadLength, 1e-4) << d;
    EXPECT_FALSE(c[0].closed);
  }
}

TEST(ParseSvg, SmoothCommandsReflectTheLastControlPoint) {
  // S after C mirrors C's second control point: two symmetric humps, each the elevated quadratic above.
  const Curves c = parse_svg(svg("<path d=\"M0 0 C0.666666666667 1.333333333333 1.333333333333 1.333333333333 2 0 "
                                 "S3.333333333333 -1.333333333333 4 0\"/>"),
                             "s.svg");
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(curve_length(c[0]), 2 * kQuadLength, 2e-4);
  EXPECT_LT(c[0].points.row(1).minCoeff(), -0.9);  // the second hump goes down
  const Curves t = parse_svg(svg("<path d=\"M0 0 Q1 2 2 0 T4 0\"/>"), "t.svg");
  EXPECT_NEAR(curve_length(t[0]), 2 * kQuadLength, 2e-4);
  EXPECT_NEAR(t[0].points.row(1).minCoeff(), -1.0, 1e-3);
}

TEST(ParseSvg, TransformedRectHasItsCorners) {
  // rotate(90) takes (x, y) to (-y, x); the group then moves by (10, 5).
  const Curves c = parse_svg(
      svg("<g transform=\"translate(10,5)\"><rect x=\"1\" y=\"2\" width=\"3\" height=\"4\" transform=\"rotate(90)\"/>"
          "</g>"),
      "r.svg");
  ASSERT_EQ(c.size(), 1u);
  ASSERT_EQ(c[0].points.cols(), 4);
  EXPECT_TRUE(c[0].closed);
  const double expected[4][2] = {{8, 6}, {8, 9}, {4, 9}, {4, 6}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[0].points(0, i), expected[i][0], 1e-12) << i;
    EXPECT_NEAR(c[0].points(1, i), expected[i][1], 1e-12) << i;
  }
}

TEST(ParseSvg, MatrixScaleAndRotateAboutAPoint) {
  // matrix(a b c d e f) maps (x, y) to (a x + c y + e, b x + d y + f).
  Curves c = parse_svg(svg("<line x1=\"1\" y1=\"0\" x2=\"0\" y2=\"1\" transform=\"matrix(1 2 3 4 5 6)\"/>"), "m.svg");
  EXPECT_EQ(c[0].points.col(0), Eigen::Vector2d(6, 8));
  EXPECT_EQ(c[0].points.col(1), Eigen::Vector2d(8, 10));
  c = parse_svg(svg("<circle cx=\"1\" cy=\"1\" r=\"1\" transform=\"scale(2, 3)\"/>"), "e.svg");
  EXPECT_NEAR(c[0].points.row(0).maxCoeff(), 4.0, 1e-9);
  EXPECT_NEAR(c[0].points.row(1).maxCoeff(), 6.0, 1e-9);
  c = parse_svg(svg("<polyline points=\"2,1 3,1\" transform=\"rotate(180 1 1)\"/>"), "p.svg");
  EXPECT_NEAR(c[0].points(0, 0), 0.0, 1e-12);
  EXPECT_NEAR(c[0].points(0, 1), -1.0, 1e-12);
  EXPECT_NEAR(c[0].points(1, 1), 1.0, 1e-12);
}

TEST(ParseSvg, ArcsMakeACircle) {
  for (const std::string d : {"M1 0 A1 1 0 0 1 -1 0 A1 1 0 0 1 1 0 Z", "M1 0a1 1 0 1 1-2 0a1 1 0 1 1 2 0z",
                              "M1 0 A0.5 0.5 0 0 1 -1 0 A 1 1 0 0 1 1 0 Z"}) {  // radii too small are scaled up
    const Curves c = parse_svg(svg("<path d=\"" + d + "\"/>"), "a.svg");
    ASSERT_EQ(c.size(), 1u) << d;
    EXPECT_TRUE(c[0].closed);
    EXPECT_NEAR(curve_length(c[0]), 2 * M_PI, 1e-3) << d;
    for (Eigen::Index i = 0; i < c[0].points.cols(); ++i) EXPECT_NEAR(c[0].points.col(i).norm(), 1.0, 1e-9);
  }
  // Compact flags: "a1 1 0 11 2 0" is rx ry phi large sweep x y.
  const Curves half = parse_svg(svg("<path d=\"M-1 0a1 1 0 11 2 0\"/>"), "f.svg");
  EXPECT_NEAR(curve_length(half[0]), M_PI, 1e-3);
}

TEST(ParseSvg, LinesSubpathsAndClosing) {
  const Curves c =
      parse_svg(svg("<path d=\"M0 0 h2 v2 H0 Z m5 0 l1 0 1 1 V3 L 9,9\"/><polygon points=\"0 0 1 0 0 1\"/>"), "l.svg");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_TRUE(c[0].closed);
  EXPECT_NEAR(curve_length(c[0]), 8.0, 1e-12);
  EXPECT_FALSE(c[1].closed);  // the subpath after Z starts at the first subpath's start: (0 0) + (5 0)
  EXPECT_EQ(c[1].points.col(0), Eigen::Vector2d(5, 0));
  EXPECT_EQ(c[1].points.col(c[1].points.cols() - 1), Eigen::Vector2d(9, 9));
  EXPECT_TRUE(c[2].closed);
  EXPECT_NEAR(curve_length(c[2]), 2 + std::sqrt(2.0), 1e-12);
}

TEST(ParseSvg, SkipsMarkupThatDrawsNothing) {
  const Curves c = parse_svg(
      "<?xml version=\"1.0\"?><!DOCTYPE svg><!-- <text> in a comment --><svg><title>t</title><defs><path "
      "d=\"M0 0 L9 9\"/></defs><sodipodi:namedview id='n'/><g><rect width='2' height='1' rx='0.5'/></g></svg>",
      "k.svg");
  ASSERT_EQ(c.size(), 1u);                            // the rect; the path in <defs> is not drawn
  EXPECT_NEAR(curve_length(c[0]), 2.0 + M_PI, 1e-3);  // two straight sides of 1, four quarter circles of radius 0.5
}

TEST(ParseSvg, ErrorsNameTheElementAndFile) {
  EXPECT_NE(error_of(svg("<path d='M0 0 L1 1'/><text x='0'>hi</text>")).find("unsupported SVG element <text>"),
            std::string::npos);
  EXPECT_NE(error_of(svg("<image href='a.png'/>")).find("drawing.svg"), std::string::npos);
  EXPECT_NE(error_of(svg("<g></g>")).find("drawing.svg: no paths"), std::string::npos);
  EXPECT_NE(error_of(svg("<path d='L1 1'/>")).find("must start with a moveto"), std::string::npos);
  EXPECT_NE(error_of(svg("<path d='M0 0 L1'/>")).find("expected a number"), std::string::npos);
  EXPECT_NE(error_of("<html></html>").find("not an SVG"), std::string::npos);
  EXPECT_NE(error_of(svg("<rect width='1cm' height='1'/>")).find("width='1cm'"), std::string::npos);
  EXPECT_NE(error_of(svg("<path d='M0 0 L1 1' transform='shear(2)'/>")).find("unknown transform 'shear'"),
            std::string::npos);
}

TEST(ParsePolylines, CurvesSeparatedByBlankLines) {
  const Curves c = parse_polylines("# two curves\n0 0\n1 0\n1 1\n0 0\n\n\n2, 2\n3 3 # open\n", "p.txt");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[0].closed);
  EXPECT_EQ(c[0].points.cols(), 3);
  EXPECT_FALSE(c[1].closed);
  EXPECT_EQ(c[1].points.col(0), Eigen::Vector2d(2, 2));
  try {
    parse_polylines("0 0\n1 x\n", "bad.txt");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:2: expected 'x y'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_polylines("\n# nothing\n", "empty.txt"), IoError);
  EXPECT_THROW(parse_polylines("0 0\n\n1 1\n2 2\n", "single.txt"), IoError);
}

TEST(WriteCurves, PolylinesAndSvgRoundTrip) {
  test::TempDir dir;
  const Curves in = parse_svg(svg("<path d='M0 0 L1 0 L1 1 Z M3 3 L4 5'/>"), "in.svg");
  write_polylines(dir.path() / "c.txt", in);
  write_svg(dir.path() / "c.svg", {{in[0], "#ff0000", 0.1}, {in[1], "#000000", 0.1}}, {{{0.5, 0.5}, "#00ff00"}}, 0.05);
  for (const char* name : {"c.txt", "c.svg"}) {
    const Curves out = read_curves(dir.path() / name);
    ASSERT_EQ(out.size(), std::string(name) == "c.svg" ? 3u : 2u) << name;  // the dot is a <circle> too
    EXPECT_TRUE(out[0].closed) << name;
    EXPECT_FALSE(out[1].closed) << name;
    EXPECT_TRUE(out[0].points.isApprox(in[0].points)) << name;
    EXPECT_TRUE(out[1].points.isApprox(in[1].points)) << name;
  }
  EXPECT_THROW(read_curves(dir.path() / "c.ply"), IoError);
}

}  // namespace
}  // namespace scanfill
