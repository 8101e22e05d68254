// How far a piece of an edge stays locally Delaunay (convert/piece_reach.hpp, internal): the
// geometry of the reach, and that the fast search gives exactly what pairing every point gives.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "convert/piece_reach.hpp"

namespace sdmesh::conversion {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

UnfoldedPoint at(double x, double y) { return {x, y, 1 / y}; }

// The angle under which u sees the segment from (s, 0) to (t, 0).
double angle_seen(const UnfoldedPoint& u, double s, double t) {
    return std::abs(std::atan2(u.y, s - u.x) - std::atan2(u.y, t - u.x));
}

double widest_angle(const std::vector<UnfoldedPoint>& side, double s, double t) {
    double widest = 0;
    for (const UnfoldedPoint& u : side) widest = std::max(widest, angle_seen(u, s, t));
    return widest;
}

// The reference: every pair.
double every_pair(const std::vector<UnfoldedPoint>& above, const std::vector<UnfoldedPoint>& below,
                  const std::vector<double>& on_line, double s) {
    double t = kInfinity;
    for (const UnfoldedPoint& p : above) {
        for (const UnfoldedPoint& q : below) t = std::min(t, pair_reach(p, q, q.y / p.y, s));
        for (const double x : on_line) t = std::min(t, pair_reach(p, at(x, 0), 0, s));
    }
    return t;
}

TEST(PieceReach, IsWhereTheWidestAnglesAcrossSumToPi) {
    std::mt19937 generator(7);
    std::uniform_real_distribution<double> along(-0.5, 1.5), height(0.05, 1.0), start(0.0, 0.5);
    PieceReach reach;
    int finite = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<UnfoldedPoint> sides[2];
        for (auto& side : sides)
            for (int k = 1 + trial % 7; k > 0; --k) side.push_back(at(along(generator), height(generator)));
        const double s = start(generator), t = reach(sides[0], sides[1], {}, s);
        ASSERT_GT(t, s);
        if (t == kInfinity) {  // then no piece from s breaks: the angles' limit stays below π
            EXPECT_LE(widest_angle(sides[0], s, 1e6) + widest_angle(sides[1], s, 1e6), std::numbers::pi + 1e-6);
            continue;
        }
        ++finite;
        EXPECT_NEAR(widest_angle(sides[0], s, t) + widest_angle(sides[1], s, t), std::numbers::pi, 1e-9);
        EXPECT_LT(widest_angle(sides[0], s, s + (t - s) * 0.999) + widest_angle(sides[1], s, s + (t - s) * 0.999),
                  std::numbers::pi);
    }
    EXPECT_GT(finite, 1000);
}

TEST(PieceReach, OnAStrictBoundaryIsWhereAPointSeesARightAngle) {
    const UnfoldedPoint p = at(0.7, 0.4);
    const double t = pair_reach(p, p, 0, 0.1);
    EXPECT_NEAR(angle_seen(p, 0.1, t), std::numbers::pi / 2, 1e-12);
    EXPECT_EQ(pair_reach(p, p, 0, 0.8), kInfinity);  // p behind s never sees a right angle
}

// Points at every scale of height down to 1e-19 (the rounding of a corner on the edge's line)
// and below where 1 / y overflows, on the line itself, beyond both ends and in near-ties: the
// fast search must give bit for bit what every pair gives, as the conversion's output depends
// on it.
TEST(PieceReach, EqualsTheLeastOverEveryPairBitForBit) {
    std::mt19937 generator(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    PieceReach reach;
    for (int trial = 0; trial < 20000; ++trial) {
        auto random_point = [&]() {
            const double x = -0.3 + 1.6 * unit(generator), y = std::pow(10.0, -19 * std::pow(unit(generator), 3));
            switch (generator() % 8) {
                case 0: return at(1.0, 1e-18 * unit(generator));  // the edge's far end, rounded
                case 1: return at(0.0, 1e-19 * unit(generator));  // its near end
                case 2: return at(std::round(x * 8) / 8, y);      // shared abscissas: near-ties
                case 3: return at(x, 1e-300 * std::pow(1e-10, unit(generator)));  // 1 / y overflows
                default: return at(x, y);
            }
        };
        std::vector<UnfoldedPoint> above, below;
        std::vector<double> on_line;
        for (int k = 1 + static_cast<int>(generator() % 40); k > 0; --k) above.push_back(random_point());
        for (int k = static_cast<int>(generator() % 40); k > 0; --k) below.push_back(random_point());
        if (generator() % 2) on_line = {0.0, 1.0};
        std::erase_if(above, [](const UnfoldedPoint& u) { return !(u.y > 0); });
        std::erase_if(below, [](const UnfoldedPoint& u) { return !(u.y > 0); });
        const double s = generator() % 4 == 0 ? 0.0 : unit(generator);
        const double expected = every_pair(above, below, on_line, s), got = reach(above, below, on_line, s);
        ASSERT_TRUE(got == expected || (std::isnan(got) && std::isnan(expected)))
            << "trial " << trial << ": " << got << " against " << expected;
    }
}

}  // namespace
}  // namespace sdmesh::conversion
