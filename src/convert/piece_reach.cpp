#include "convert/piece_reach.hpp"

#include <algorithm>
#include <cmath>

namespace sdmesh::conversion {

double PieceReach::operator()(std::span<const UnfoldedPoint> above, std::span<const UnfoldedPoint> below,
                              std::span<const double> on_line, double s) {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    double t = infinity;
    if (above.empty()) return t;
    auto pair = [&](const UnfoldedPoint& p, const UnfoldedPoint& q) {
        t = std::min(t, pair_reach(p, q, q.y / p.y, s));  // a NaN (degenerate points) leaves t
    };
    for (const double x : on_line) pair(above.front(), {x, 0, infinity});  // κ = 0: the same for every p
    if (below.empty()) return t;
    // Pairing every p with every q costs their product for each point placed (tulip.obj: 5.8e9
    // pairs). A point's cotangent for s-t falls as t grows, so the two sides' smallest at t, if
    // they sum below 0, pair into a reach below t (Dinkelbach's step). A few steps come close;
    // then only the pairs whose sum at t is below 0 within rounding can reach lower.
    // cotangents_at_t() gives each point's cotangent times t - s (at t = ∞ the cotangent's
    // limit), less `rounding` times a bound on its rounding error, and the smallest's index;
    // false for a NaN.
    auto cotangents_at_t = [&](int side, double rounding, size_t& smallest) {
        std::vector<double>& out = cotangents_[side];
        out.clear();
        smallest = 0;
        bool numbers = true;
        for (const UnfoldedPoint& u : side == 0 ? above : below) {
            // t is rounded, and the cotangent moves by |u.x - s| / u.y per unit of it: that
            // term dominates the bound.
            const double from_s = u.x - s;
            const double along = t == infinity ? -from_s - rounding * std::abs(from_s)
                                               : from_s * (u.x - t) - rounding * std::abs(from_s) * (std::abs(u.x) + t);
            // Below a height of 1 / DBL_MAX the inverse overflows where the quotient may not.
            const double over_height = std::isinf(u.inverse_y) ? along / u.y : along * u.inverse_y;
            out.push_back(t == infinity ? over_height : over_height + u.y * (1 - rounding));
            numbers = numbers && !std::isnan(out.back());
            if (out.back() < out[smallest]) smallest = out.size() - 1;
        }
        return numbers;
    };
    constexpr int steps = 8;
    size_t i = 0, j = 0;
    for (int step = 0; step < steps && t > s; ++step) {
        cotangents_at_t(0, 0, i);
        cotangents_at_t(1, 0, j);
        if (!(cotangents_[0][i] + cotangents_[1][j] < 0)) break;
        const double lower = pair_reach(above[i], below[j], below[j].y / above[i].y, s);
        if (!(lower < t)) break;
        t = lower;
    }
    constexpr double rounding = 1e-10;
    if (t > s && cotangents_at_t(0, rounding, i) && cotangents_at_t(1, rounding, j)) {
        // A NaN sum (∞ - ∞: two points so near the line that their cotangents overflow) is
        // paired too.
        for (size_t p = 0; p < above.size(); ++p)
            if (!(cotangents_[0][p] + cotangents_[1][j] >= 0))
                for (size_t q = 0; q < below.size(); ++q)
                    if (!(cotangents_[0][p] + cotangents_[1][q] >= 0)) pair(above[p], below[q]);
    } else {  // rounding beyond the bounds: every pair
        for (const UnfoldedPoint& p : above)
            for (const UnfoldedPoint& q : below) pair(p, q);
    }
    return t;
}

}  // namespace sdmesh::conversion
