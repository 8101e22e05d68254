#pragma once
// Triangle quantities from edge lengths alone, with cancellation-safe formulas, so that the same
// code serves meshes with positions and intrinsic triangulations.
//
// In every function, `opposite` is the length of the side opposite the angle in question and
// `b`, `c` the two sides adjacent to it. Lengths must be finite and >= 0.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace sdmesh {

/// |p - q|², summed in a fixed order ((x² + y²) + z²), so that every module computes the same bits
/// for the same edge, whichever end it starts from.
[[nodiscard]] inline double squared_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    const double dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
    return (dx * dx + dy * dy) + dz * dz;
}

/// |p - q|, the square root of squared_distance(p, q).
[[nodiscard]] inline double distance(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return std::sqrt(squared_distance(p, q));
}

/// The exponent e with 2^e <= length < 2^(e+1), or 0 for a length that is 0 or not finite.
/// Coordinates divided by 2^e (exactly) span about 1, so that products of a few lengths neither
/// overflow nor underflow; results are multiplied back as exactly.
[[nodiscard]] inline int unit_exponent(double length) {
    return length > 0 && std::isfinite(length) ? std::ilogb(length) : 0;
}

/// unit_exponent(length) when it lies beyond ±64, else 0. Within 2^±64 of 1 products of a few
/// lengths stay far inside the double range, and scaling by a power of two (exact) would not
/// change a bit of the results: callers that must copy their input to scale it skip the copy.
[[nodiscard]] inline int far_unit_exponent(double length) {
    constexpr int kNearOne = 64;
    const int exponent = unit_exponent(length);
    return exponent > kNearOne || exponent < -kNearOne ? exponent : 0;
}

/// Triangle area from its three side lengths by Kahan's formula (accurate also for needles).
/// Lengths that violate the triangle inequality (by rounding or otherwise) give 0.
[[nodiscard]] inline double triangle_area(double a, double b, double c) {
    // Kahan, "Miscalculating area and angles of a needle-like triangle": sort a >= b >= c and
    // keep the parentheses exactly as written. The sort by min and max has no branch to mispredict.
    // The four factors go under two square roots, two by two, so that nothing is raised above the
    // square of a length: lengths from 1e-150 to 1e150 neither overflow nor underflow.
    const double hi = std::max(a, b), lo = std::min(a, b);
    const double largest = std::max(hi, c), middle = std::max(lo, std::min(hi, c)), smallest = std::min(lo, c);
    const double outer = (largest + (middle + smallest)) * (largest + (middle - smallest));  // > 0
    const double inner = (smallest - (largest - middle)) * (smallest + (largest - middle));  // ≤ 0 if degenerate
    return inner > 0 ? 0.25 * (std::sqrt(outer) * std::sqrt(inner)) : 0.0;
}

/// b² + c² - opposite² (= 2bc·cos of the angle), evaluated as (p - o)(p + o) + q² with
/// p = max(b,c), q = min(b,c): its error is O(eps·b·c), so angles near 0, π/2 and π stay accurate.
[[nodiscard]] inline double cosine_numerator(double opposite, double b, double c) {
    const double p = std::max(b, c), q = std::min(b, c);
    return (p - opposite) * (p + opposite) + q * q;
}

/// The angle opposite `opposite`, in [0, π], as atan2(4·area, b² + c² - opposite²).
[[nodiscard]] double corner_angle(double opposite, double b, double c);

/// Whether the angle opposite `opposite` is below the acute angle whose tangent is `tangent`:
/// corner_angle's comparison without its arctangent (4·area < tangent · (b² + c² - opposite²)).
[[nodiscard]] inline bool corner_below(double opposite, double b, double c, double tangent) {
    const double cosine = cosine_numerator(opposite, b, c);
    return cosine > 0 && 4.0 * triangle_area(opposite, b, c) < tangent * cosine;
}

/// Cotangent of the angle opposite `opposite` (± infinity for a zero-area triangle).
[[nodiscard]] double corner_cotangent(double opposite, double b, double c);

/// Circumcentre of a triangle in space; non-finite for a degenerate triangle.
[[nodiscard]] Eigen::Vector3d circumcenter(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                           const Eigen::Vector3d& c);

}  // namespace sdmesh
