// Exact point-triangle distance (Ericson's Voronoi-region walk) in double.
#include "boundary/point_triangle.hpp"

#include <algorithm>

namespace pfill {
namespace {

PointTriangleResult make_result(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double u, double v,
                                TriangleFeature feature) {
  PointTriangleResult r;
  r.u = u;
  r.v = v;
  r.point = a * (1.0 - u - v) + b * u + c * v;
  r.feature = feature;
  const Vec3 d = p - r.point;
  r.distance2 = dot(d, d);
  return r;
}

// Closest point on segment [s0, s1] as a parameter t in [0, 1].
double segment_parameter(const Vec3& p, const Vec3& s0, const Vec3& s1) {
  const Vec3 e = s1 - s0;
  const double ee = dot(e, e);
  if (ee <= 0) return 0;
  return std::clamp(dot(p - s0, e) / ee, 0.0, 1.0);
}

// Zero-area triangles have no face region: take the best of the three edges.
PointTriangleResult closest_on_degenerate(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  auto edge_feature = [](double t, TriangleFeature edge, TriangleFeature v0, TriangleFeature v1) {
    return t <= 0 ? v0 : (t >= 1 ? v1 : edge);
  };
  const double tab = segment_parameter(p, a, b);
  const double tbc = segment_parameter(p, b, c);
  const double tca = segment_parameter(p, c, a);
  PointTriangleResult best = make_result(p, a, b, c, tab, 0,
                                         edge_feature(tab, TriangleFeature::EdgeAB, TriangleFeature::VertexA,
                                                      TriangleFeature::VertexB));
  const PointTriangleResult rbc = make_result(
      p, a, b, c, 1 - tbc, tbc,
      edge_feature(tbc, TriangleFeature::EdgeBC, TriangleFeature::VertexB, TriangleFeature::VertexC));
  const PointTriangleResult rca = make_result(
      p, a, b, c, 0, 1 - tca,
      edge_feature(tca, TriangleFeature::EdgeCA, TriangleFeature::VertexC, TriangleFeature::VertexA));
  if (rbc.distance2 < best.distance2) best = rbc;
  if (rca.distance2 < best.distance2) best = rca;
  return best;
}

}  // namespace

PointTriangleResult closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 n = cross(ab, ac);
  const double scale2 = std::max(dot(ab, ab), dot(ac, ac));
  // Relative test: a sliver whose area is at rounding level has no usable plane.
  if (dot(n, n) <= 1e-24 * scale2 * scale2) return closest_on_degenerate(p, a, b, c);

  const Vec3 ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return make_result(p, a, b, c, 0, 0, TriangleFeature::VertexA);

  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return make_result(p, a, b, c, 1, 0, TriangleFeature::VertexB);

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return make_result(p, a, b, c, d1 / (d1 - d3), 0, TriangleFeature::EdgeAB);

  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return make_result(p, a, b, c, 0, 1, TriangleFeature::VertexC);

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return make_result(p, a, b, c, 0, d2 / (d2 - d6), TriangleFeature::EdgeCA);

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return make_result(p, a, b, c, 1 - t, t, TriangleFeature::EdgeBC);
  }

  const double denom = 1.0 / (va + vb + vc);
  return make_result(p, a, b, c, vb * denom, vc * denom, TriangleFeature::Face);
}

}  // namespace pfill
