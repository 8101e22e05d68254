#include "sdmesh/topology.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "union_find.hpp"

namespace sdmesh {
namespace {

// Corners of one vertex are in one fan when joined through manifold edges:
// fans(v) = corners(v) - successful unions at v.
std::vector<int> find_nonmanifold_vertices(const Eigen::MatrixX3i& F, const EdgeTable& table,
                                           const std::vector<char>& valid_face, int num_vertices) {
    const int num_faces = static_cast<int>(F.rows());
    UnionFind corners(3 * num_faces);
    std::vector<int> fans(static_cast<size_t>(num_vertices), 0);
    for (int k = 0; k < 3; ++k)
        for (int f = 0; f < num_faces; ++f) fans[F(f, k)] += valid_face[f];
    // The corner of halfedge h's face at vertex v, one of h's two endpoints.
    auto corner_at = [&F](int h, int v) {
        const int f = h / 3, next = (h % 3 + 1) % 3;
        return 3 * f + (F(f, next) == v ? next : (next + 1) % 3);
    };
    for (int e = 0; e < table.num_edges(); ++e) {
        if (table.face_count[e] != 2) continue;
        const int h0 = table.edge_halfedges(e, 0), h1 = table.edge_halfedges(e, 1);
        for (int side = 0; side < 2; ++side) {
            const int v = table.E(e, side);
            if (corners.unite(corner_at(h0, v), corner_at(h1, v))) --fans[v];
        }
    }
    std::vector<int> result;
    for (int v = 0; v < num_vertices; ++v)
        if (fans[v] > 1) result.push_back(v);
    return result;
}

}  // namespace

EdgeTable build_edge_table(const Eigen::MatrixX3i& F, int num_vertices) {
    const int num_faces = static_cast<int>(F.rows());
    std::vector<char> valid_face(static_cast<size_t>(num_faces));
    for (int f = 0; f < num_faces; ++f) valid_face[f] = !has_repeated_index(F, f);

    // Bucket the halfedges of valid faces by their lower endpoint (counting sort); within a
    // bucket they are kept as 64-bit keys (upper endpoint, halfedge), so sorting a bucket orders
    // it by upper endpoint and then by halfedge, which makes the numbering unique.
    std::vector<int> bucket_start(static_cast<size_t>(num_vertices) + 1, 0);
    for (int k = 0; k < 3; ++k)
        for (int f = 0; f < num_faces; ++f)
            if (valid_face[f]) ++bucket_start[std::min(F(f, (k + 1) % 3), F(f, (k + 2) % 3)) + 1];
    std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
    std::vector<std::uint64_t> keys(static_cast<size_t>(bucket_start.back()));
    {
        std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
        for (int k = 0; k < 3; ++k)
            for (int f = 0; f < num_faces; ++f) {
                if (!valid_face[f]) continue;
                const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
                const auto [lo, hi] = std::minmax(a, b);
                keys[fill[lo]++] = (std::uint64_t(hi) << 32) | std::uint32_t(3 * f + k);
            }
    }

    EdgeTable table;
    table.face_edge.setConstant(num_faces, 3, -1);
    std::vector<int> lo_of, hi_of, first, second;
    lo_of.reserve(keys.size() / 2 + 1);
    hi_of.reserve(keys.size() / 2 + 1);
    first.reserve(keys.size() / 2 + 1);
    second.reserve(keys.size() / 2 + 1);
    table.face_count.reserve(keys.size() / 2 + 1);
    for (int v = 0; v < num_vertices; ++v) {
        const auto begin = keys.begin() + bucket_start[v], end = keys.begin() + bucket_start[v + 1];
        std::sort(begin, end);
        for (auto run = begin; run != end;) {
            const std::uint64_t hi = *run >> 32;
            const int e = static_cast<int>(lo_of.size());
            lo_of.push_back(v);
            hi_of.push_back(static_cast<int>(hi));
            first.push_back(static_cast<int>(*run & 0xffffffffu));
            second.push_back(-1);
            int count = 0;
            for (; run != end && (*run >> 32) == hi; ++run, ++count) {
                const int h = static_cast<int>(*run & 0xffffffffu);
                table.face_edge(h / 3, h % 3) = e;
                if (count == 1) second.back() = h;
            }
            table.face_count.push_back(count);
        }
    }
    const auto num_edges = static_cast<Eigen::Index>(lo_of.size());
    table.E.resize(num_edges, 2);
    table.E.col(0) = Eigen::Map<const Eigen::VectorXi>(lo_of.data(), num_edges);
    table.E.col(1) = Eigen::Map<const Eigen::VectorXi>(hi_of.data(), num_edges);
    table.edge_halfedges.resize(num_edges, 2);
    table.edge_halfedges.col(0) = Eigen::Map<const Eigen::VectorXi>(first.data(), num_edges);
    table.edge_halfedges.col(1) = Eigen::Map<const Eigen::VectorXi>(second.data(), num_edges);
    table.nonmanifold_vertices = find_nonmanifold_vertices(F, table, valid_face, num_vertices);
    return table;
}

}  // namespace sdmesh
