// Triangle and hinge formulas from edge lengths: accuracy on needles, near-right and
// near-co-circular cases, and agreement of the three local Delaunay tests.

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/geometry.hpp"

namespace sdmesh {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(TriangleArea, RightAndEquilateral) {
    EXPECT_DOUBLE_EQ(triangle_area(3, 4, 5), 6.0);
    EXPECT_DOUBLE_EQ(triangle_area(5, 3, 4), 6.0);
    EXPECT_NEAR(triangle_area(1, 1, 1), std::sqrt(3.0) / 4, 1e-16);
}

TEST(TriangleArea, NeedleIsRelativelyAccurate) {
    // Isosceles needle: sides 1, 1, b. Exact area b/2 · sqrt(1 - b²/4).
    for (double b : {1e-3, 1e-6, 1e-9, 1e-12}) {
        const double exact = b / 2 * std::sqrt(1 - b * b / 4);
        EXPECT_NEAR(triangle_area(1, 1, b) / exact, 1.0, 1e-14) << "b = " << b;
    }
}

// Nothing is raised above the square of a length: the whole range where squared lengths exist.
TEST(TriangleArea, ScalesFrom1e150To1e_150) {
    for (const double scale : {1e150, 1e100, 1e-100, 1e-150})
        EXPECT_NEAR(triangle_area(3 * scale, 4 * scale, 5 * scale) / (scale * scale), 6.0, 1e-14) << scale;
}

TEST(TriangleArea, ViolatedInequalityGivesZero) {
    EXPECT_EQ(triangle_area(1, 1, 3), 0.0);
    EXPECT_EQ(triangle_area(1, 2, 3), 0.0);  // collinear
}

TEST(CornerAngle, AccurateAtZeroRightAndStraight) {
    EXPECT_NEAR(corner_angle(5, 3, 4), kPi / 2, 1e-15);
    // Angle opposite a tiny side: acos of a dot product would lose it entirely.
    for (double s : {1e-4, 1e-8, 1e-12}) EXPECT_NEAR(corner_angle(s, 1, 1) / (2 * std::asin(s / 2)), 1.0, 1e-14);
    // Nearly straight angle: sides 1, 1 and 2 - d.
    for (double d : {1e-4, 1e-8}) {
        const double half_gap = std::acos(1 - d / 2);  // angle at the base corners
        EXPECT_NEAR(kPi - corner_angle(2 - d, 1, 1), 2 * half_gap, 1e-7 * half_gap) << "d = " << d;
    }
}

TEST(CornerCotangent, MatchesAngle) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.1, 1.0);
    for (int i = 0; i < 1000; ++i) {
        const double a = u(rng), b = u(rng), c = u(rng);
        if (triangle_area(a, b, c) < 1e-3) continue;
        EXPECT_NEAR(corner_cotangent(a, b, c), 1.0 / std::tan(corner_angle(a, b, c)), 1e-9);
    }
}

// A planar hinge with edge p = (0,0), q = (1,0); r above, s below. Returns the lengths
// (l, a, b, c, d) and the opposite angles measured with vectors.
struct Hinge {
    double l, a, b, c, d, alpha, beta;
};

Hinge planar_hinge(double rx, double ry, double sx, double sy) {
    auto angle_at = [](double x, double y) {  // angle at (x, y) between p and q
        const double ux = -x, uy = -y, vx = 1 - x, vy = -y;
        return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy);
    };
    return {1.0,
            std::hypot(rx, ry),      std::hypot(rx - 1, ry),
            std::hypot(sx, sy),      std::hypot(sx - 1, sy),
            angle_at(rx, ry),        angle_at(sx, sy)};
}

TEST(DelaunayMargin, EqualsPiMinusOppositeAngles) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> x(-1.0, 2.0), y(0.01, 2.0);
    for (int i = 0; i < 10000; ++i) {
        const Hinge h = planar_hinge(x(rng), y(rng), x(rng), -y(rng));
        EXPECT_NEAR(delaunay_margin(h.l, h.a, h.b, h.c, h.d), kPi - h.alpha - h.beta, 1e-12);
    }
}

TEST(DelaunayMargin, SquareIsCoCircular) {
    const double d = std::sqrt(2.0);
    EXPECT_NEAR(delaunay_margin(d, 1, 1, 1, 1), 0.0, 1e-15);
    EXPECT_NEAR(boundary_margin(d, 1, 1), 0.0, 1e-15);
}

// π - (α + β) evaluated from the same lengths in long double, as the reference for the accuracy
// of the double-precision formulas (the lengths themselves are the data; coordinates are not).
double reference_margin(double l, double a, double b, double c, double d) {
    auto angle = [](long double o, long double x, long double y) {
        long double s[3] = {o, x, y};
        std::sort(s, s + 3, std::greater<>());
        const long double product = (s[0] + (s[1] + s[2])) * (s[2] - (s[0] - s[1])) *
                                    (s[2] + (s[0] - s[1])) * (s[0] + (s[1] - s[2]));
        return std::atan2(std::sqrt(std::max(product, 0.0L)), x * x + y * y - o * o);
    };
    return static_cast<double>(std::numbers::pi_v<long double> - angle(l, a, b) - angle(l, c, d));
}

// 10^5 random hinges (a third generic, a third within 1e-3..1e-13 of co-circular, a third with
// needles): the margin, the cotan weight and the sqrt-free test give the same verdict wherever
// the margin is clear of zero by more than the rounding error.
TEST(DelaunayMargin, ThreeTestsAgreeOnRandomHinges) {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0, near_cocircular = 0;
    for (int i = 0; i < 100000; ++i) {
        double rx = -1 + 3 * unit(rng), ry = 0.01 + 2 * unit(rng);
        double sx, sy;
        if (i % 3 == 0) {
            sx = -1 + 3 * unit(rng);
            sy = -0.01 - 2 * unit(rng);
        } else if (i % 3 == 1) {
            // s on the circle through p, q, r, moved radially by eps.
            const double cx = 0.5, cy = (rx * rx - rx + ry * ry) / (2 * ry);
            const double radius = std::hypot(cx, cy);
            const double eps = std::pow(10.0, -3 - 10 * unit(rng)) * (unit(rng) < 0.5 ? -1 : 1);
            // The arc below the edge line is t in -π/2 ± acos(cy / radius).
            const double half_arc = std::acos(std::clamp(cy / radius, -1.0, 1.0));
            const double t = -kPi / 2 + 0.9 * half_arc * (2 * unit(rng) - 1);
            sx = cx + radius * (1 + eps) * std::cos(t);
            sy = cy + radius * (1 + eps) * std::sin(t);
            ++near_cocircular;
        } else {
            // Needles: r or s very close to the edge line, or far away.
            const double scale = std::pow(10.0, -6 * unit(rng));
            ry *= scale;
            sx = -1 + 3 * unit(rng);
            sy = -std::pow(10.0, -6 + 9 * unit(rng));
        }
        const Hinge h = planar_hinge(rx, ry, sx, sy);
        const double margin = delaunay_margin(h.l, h.a, h.b, h.c, h.d);
        EXPECT_NEAR(margin, reference_margin(h.l, h.a, h.b, h.c, h.d), 1e-13) << "hinge " << i;
        // Lengths rounded to double fix the angles only to ~sqrt(eps) on nearly flat triangles.
        EXPECT_NEAR(margin, kPi - h.alpha - h.beta, 1e-6) << "hinge " << i;
        if (std::abs(margin) < 1e-9) continue;
        ++checked;
        EXPECT_EQ(is_locally_delaunay(h.l, h.a, h.b, h.c, h.d), margin >= -kDelaunayTolerance) << "hinge " << i;
        const bool ld = margin > 0;
        EXPECT_EQ(is_delaunay_sqrt_free(h.l, h.a, h.b, h.c, h.d), ld) << "hinge " << i;
        EXPECT_EQ(cotan_weight(h.l, h.a, h.b, h.c, h.d) > 0, ld) << "hinge " << i;
    }
    EXPECT_GT(checked, 85000);
    EXPECT_GT(near_cocircular, 30000);
}

TEST(DelaunayMargin, ScaleInvariant) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> x(-1.0, 2.0), y(0.01, 2.0);
    for (int i = 0; i < 1000; ++i) {
        const Hinge h = planar_hinge(x(rng), y(rng), x(rng), -y(rng));
        const double m = delaunay_margin(h.l, h.a, h.b, h.c, h.d);
        for (double k : {1e8, 1e-8}) {
            EXPECT_NEAR(delaunay_margin(k * h.l, k * h.a, k * h.b, k * h.c, k * h.d), m, 1e-12);
            EXPECT_EQ(is_delaunay_sqrt_free(k * h.l, k * h.a, k * h.b, k * h.c, k * h.d),
                      is_delaunay_sqrt_free(h.l, h.a, h.b, h.c, h.d));
        }
    }
}

TEST(Circumcenter, EquidistantAndInPlane) {
    const Eigen::Vector3d a(0.3, -1, 2), b(1, 0.5, 0), c(-2, 1, 1);
    const Eigen::Vector3d o = circumcenter(a, b, c);
    EXPECT_NEAR((o - a).norm(), (o - b).norm(), 1e-12);
    EXPECT_NEAR((o - a).norm(), (o - c).norm(), 1e-12);
    EXPECT_NEAR((o - a).dot((b - a).cross(c - a)), 0.0, 1e-12);
}

}  // namespace
}  // namespace sdmesh
