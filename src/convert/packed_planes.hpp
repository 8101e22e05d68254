#pragma once
// The points of the input's planes, packed for point removal's scans (internal, not installed):
// which points see a piece of an edge widest. Read from scattered positions, those scans were
// most of the removal's time on planes of thousands of points.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sdmesh::conversion {

// How far from the middle of a segment of half-length `half` a point can lie that sees it under
// an angle whose cotangent is below c. Those points lie inside the arcs through the segment's
// ends of that inscribed angle (rotated about it, out of any one plane): for c >= 0 the arcs'
// middles are the farthest, half · (sqrt(1 + c²) + c) away; for c < 0 (obtuse) the segment's ends.
// Widened by a millionth against rounding; not finite where c is +inf or NaN.
inline double apex_reach(double half, double c) {
    return (c < 0 ? half : half * (std::hypot(1.0, c) + c)) * (1 + 1e-6);
}

// Points in groups (the planes), each group packed in a row and sorted along the axis of its
// longest extent, so that a scan of the points near a place reads a slice of it. Points added
// to a group after it is built go unsorted at its end and are read by every scan.
class PackedPlanes {
public:
    struct Point {
        Eigen::Vector3d position;
        int id, edge;
    };

    explicit PackedPlanes(int planes) : index_(static_cast<size_t>(planes), -1) {}

    bool built(int plane) const { return index_[plane] >= 0; }
    // \pre !built(plane)
    void build(int plane, std::vector<Point> points) {
        index_[plane] = static_cast<int>(groups_.size());
        Group& group = groups_.emplace_back();
        Eigen::AlignedBox3d box;
        for (const Point& point : points) box.extend(point.position);
        if (!points.empty()) box.sizes().maxCoeff(&group.axis);
        std::sort(points.begin(), points.end(), [axis = group.axis](const Point& one, const Point& other) {
            return std::pair(one.position[axis], one.id) < std::pair(other.position[axis], other.id);
        });
        group.sorted = points.size();
        group.points = std::move(points);
    }
    // \pre built(plane)
    void add(int plane, const Point& point) { groups_[index_[plane]].points.push_back(point); }
    // \pre built(plane)
    std::span<const Point> points(int plane) const { return groups_[index_[plane]].points; }

    // Calls visit(point) for every point of the plane within `reach` of `middle` along its
    // axis, and for the points added since it was built (for all of them where reach is not
    // finite). \pre built(plane)
    template <class Visit>
    void for_each_near(int plane, const Eigen::Vector3d& middle, double reach, Visit&& visit) const {
        const Group& group = groups_[index_[plane]];
        auto near = group.points.begin(), far = near + static_cast<std::ptrdiff_t>(group.sorted);
        std::for_each(far, group.points.end(), visit);
        if (reach < std::numeric_limits<double>::infinity()) {
            const double low = middle[group.axis] - reach, high = middle[group.axis] + reach;
            near = std::partition_point(near, far, [&](const Point& y) { return y.position[group.axis] < low; });
            far = std::partition_point(near, far, [&](const Point& y) { return y.position[group.axis] <= high; });
        }
        std::for_each(near, far, visit);
    }

private:
    struct Group {
        std::vector<Point> points;
        size_t sorted = 0;  // the first `sorted` points, by position[axis]
        int axis = 0;
    };
    std::vector<int> index_;  // by plane: its group, -1 before it is built
    std::vector<Group> groups_;
};

}  // namespace sdmesh::conversion
