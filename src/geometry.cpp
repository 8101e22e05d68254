#include "sdmesh/geometry.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace sdmesh {

double corner_angle(double opposite, double b, double c) {
    return std::atan2(4.0 * triangle_area(opposite, b, c), cosine_numerator(opposite, b, c));
}

double corner_cotangent(double opposite, double b, double c) {
    return cosine_numerator(opposite, b, c) / (4.0 * triangle_area(opposite, b, c));
}

Eigen::Vector3d circumcenter(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
    const Eigen::Vector3d u = b - a, v = c - a;
    const Eigen::Vector3d n = u.cross(v);
    return a + (u.squaredNorm() * v - v.squaredNorm() * u).cross(n) / (2.0 * n.squaredNorm());
}

}  // namespace sdmesh
