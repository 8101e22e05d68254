// Point removal's packed planes (convert/packed_planes.hpp, internal): the ball that holds every
// point seeing a piece wider than a given angle, and scans that read only the points near it.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "convert/converter.hpp"
#include "convert/packed_planes.hpp"

namespace sdmesh::conversion {
namespace {

TEST(ApexReach, HoldsEveryPointThatSeesThePieceWiderAndIsTight) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> coordinate(-2, 2), cotangent(-3, 3);
    int wider = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Eigen::Vector3d p(coordinate(random), coordinate(random), coordinate(random));
        const Eigen::Vector3d q(coordinate(random), coordinate(random), coordinate(random));
        const Eigen::Vector3d middle = (p + q) / 2;
        const double c = cotangent(random), half = (q - p).norm() / 2, reach = apex_reach(half, c);
        for (int k = 0; k < 50; ++k) {
            // Points anywhere in space, not only in a plane through p and q.
            const Eigen::Vector3d y = middle + Eigen::Vector3d(coordinate(random), coordinate(random), coordinate(random));
            if (!(cotangent_seen_from(y, p, q) < c)) continue;
            ++wider;
            EXPECT_LE((y - middle).norm(), reach) << "trial " << trial;
        }
        // The arc's point farthest from the middle (its own middle where c >= 0, else p) sees
        // p-q under cotangent c, at the reach but for the widening.
        const Eigen::Vector3d across = (q - p).cross(Eigen::Vector3d(0.3, -0.5, 0.8)).normalized();
        const Eigen::Vector3d far = c >= 0 ? Eigen::Vector3d(middle + across * half * (std::hypot(1.0, c) + c)) : p;
        EXPECT_NEAR((far - middle).norm(), reach / (1 + 1e-6), 1e-12 * reach);
        if (c >= 0) {
            EXPECT_NEAR(cotangent_seen_from(far, p, q), c, 1e-9 * (1 + c));
        }
    }
    EXPECT_GT(wider, 10000);
    EXPECT_EQ(apex_reach(1, std::numeric_limits<double>::infinity()), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(std::isnan(apex_reach(1, std::numeric_limits<double>::quiet_NaN())));
}

TEST(PackedPlanes, ScansReadThePointsNearAlongTheLongestAxisAndEveryAddedOne) {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> along(-10, 10), across(-1, 1), unit(0, 1);
    PackedPlanes planes(3);
    // Plane 1: a strip along y; its points are read in slices of y.
    std::vector<PackedPlanes::Point> points;
    for (int id = 0; id < 400; ++id) points.push_back({{across(random), along(random), 0.0}, id, id % 7 - 1});
    EXPECT_FALSE(planes.built(1));
    planes.build(1, points);
    EXPECT_TRUE(planes.built(1));
    EXPECT_FALSE(planes.built(0));
    const PackedPlanes::Point added{{0.0, 50.0, 0.0}, 400, 3};
    planes.add(1, added);
    points.push_back(added);
    ASSERT_EQ(planes.points(1).size(), points.size());
    for (int trial = 0; trial < 200; ++trial) {
        const Eigen::Vector3d middle(across(random), along(random), 0);
        const double reach = trial == 0 ? std::numeric_limits<double>::infinity() : 3 * unit(random);
        std::multiset<int> read, expected;
        planes.for_each_near(1, middle, reach, [&](const PackedPlanes::Point& point) { read.insert(point.id); });
        for (const PackedPlanes::Point& point : points)
            if (point.id == added.id || std::abs(point.position.y() - middle.y()) <= reach) expected.insert(point.id);
        EXPECT_EQ(read, expected) << "trial " << trial;
        if (trial > 0) {
            EXPECT_LT(read.size(), points.size() / 2);
        }
    }
    // An empty plane reads nothing.
    planes.build(2, {});
    int visits = 0;
    planes.for_each_near(2, Eigen::Vector3d::Zero(), 1, [&](const PackedPlanes::Point&) { ++visits; });
    EXPECT_EQ(visits, 0);
}

}  // namespace
}  // namespace sdmesh::conversion
