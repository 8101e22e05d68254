#pragma once
// How far a piece of an input edge can run before it stops being locally Delaunay, from the
// points of the two faces beside the edge unfolded into its line (internal, not installed):
// fewest_points_per_edge places each point just short of it.

#include <limits>
#include <span>
#include <vector>

namespace sdmesh::conversion {

// A point of a face beside the edge: along the edge from its start, its height off the edge's
// line and the height's inverse (which the reach multiplies by for every point it places).
struct UnfoldedPoint {
    double x, y, inverse_y;
};

// Where the piece from s to t stops being locally Delaunay against p and q: p and q (at heights
// p.y and -q.y) see s-t under angles summing to π where q lies on the circle through s, t and p:
// (q.x - s)(q.x - t) + q.y² + κ((p.x - s)(p.x - t) + p.y²) = 0 with κ = q.y / p.y, linear in
// t. With κ = 0 and q = p: where p sees it under π/2 (a strict boundary). +inf for never.
inline double pair_reach(const UnfoldedPoint& p, const UnfoldedPoint& q, double kappa, double s) {
    const double slope = (q.x - s) + kappa * (p.x - s);
    const double rest = q.x * (q.x - s) + q.y * q.y + kappa * (p.x * (p.x - s) + p.y * p.y);
    return slope > 0 ? rest / slope : std::numeric_limits<double>::infinity();
}

// The least pair_reach over p in `above` and q in `below`, and over the points of side 1 on the
// edge's line (their x in `on_line`, κ = 0) paired with any p: exactly what pairing them all
// gives, in time linear in the points but for near-ties. +inf where `above` is empty.
class PieceReach {
public:
    double operator()(std::span<const UnfoldedPoint> above, std::span<const UnfoldedPoint> below,
                      std::span<const double> on_line, double s);

private:
    std::vector<double> cotangents_[2];  // scratch, kept between calls
};

}  // namespace sdmesh::conversion
