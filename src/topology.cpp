#include "sdmesh/topology.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <numeric>

#include "prefault.hpp"


namespace sdmesh {
namespace {

// A vertex is manifold when walking from one of its corners across the manifold edges around it
// (both ways where the fan is open) reaches all of its corners. Each walk stays inside one
// vertex's star, so the vertices are independent and the loop runs in parallel.
std::vector<int> find_nonmanifold_vertices(const Eigen::MatrixX3i& F, const EdgeTable& table,
                                           const std::vector<char>& valid_face, int num_vertices) {
    const int num_faces = static_cast<int>(F.rows());
    // A walk step reads one face: the vertex of each corner, and across each side (the side
    // opposite corner k is halfedge 3f + k) the other halfedge of a manifold edge, else -1.
    struct FaceRecord {
        int vertex[3];
        int twin[3];
    };
    const std::unique_ptr<FaceRecord[]> face(new FaceRecord[static_cast<size_t>(num_faces)]);  // all written below
    detail::prefault(face.get(), sizeof(FaceRecord) * static_cast<size_t>(num_faces));
#pragma omp parallel for schedule(static)
    for (int f = 0; f < num_faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const int e = table.face_edge(f, k), h = 3 * f + k;
            face[f].vertex[k] = F(f, k);
            face[f].twin[k] = e < 0 || table.face_count[e] != 2 ? -1
                              : table.edge_halfedges(e, 0) == h ? table.edge_halfedges(e, 1)
                                                                : table.edge_halfedges(e, 0);
        }
    std::vector<int> corners, first;
    detail::prefaulted_assign(corners, static_cast<size_t>(num_vertices), 0);
    detail::prefaulted_assign(first, static_cast<size_t>(num_vertices), -1);
    for (int f = 0; f < num_faces; ++f) {
        if (!valid_face[f]) continue;
        for (int k = 0; k < 3; ++k) {
            const int v = face[f].vertex[k];
            ++corners[v];
            if (first[v] < 0) first[v] = 3 * f + k;
        }
    }
    // Corner c = 3f + k touches the two sides next(c) and prev(c) of its face. The walk crosses a
    // side to the twin's face, finds the vertex's corner there and leaves by that face's other
    // side at the vertex; this does not assume a consistent orientation.
    auto next = [](int c) { return c - c % 3 + (c % 3 + 1) % 3; };
    auto prev = [](int c) { return c - c % 3 + (c % 3 + 2) % 3; };
    // A walk waits on memory at every step (the faces around a vertex lie anywhere), so each
    // thread runs kLanes walks side by side, a step of each in turn, and each lane asks for the
    // face it steps into a round before it reads it: the reads overlap.
    struct Walk {
        int v = -1, start = 0, across = -1, seen = 0;
        bool backwards = false;  // second leg: from next(start) instead of prev(start)
    };
    constexpr int kLanes = 8, kChunk = 4096;
    std::vector<char> bad(static_cast<size_t>(num_vertices), 0);
    const int num_chunks = (num_vertices + kChunk - 1) / kChunk;
#pragma omp parallel for schedule(dynamic, 1)
    for (int chunk = 0; chunk < num_chunks; ++chunk) {
        int pending = chunk * kChunk;
        const int end = std::min(pending + kChunk, num_vertices);
        // Crossing `side`: its twin comes from its own face (just read, after a step), and the
        // face across is fetched for the next round.
        const auto cross = [&](Walk& w, int side) {
            w.across = face[side / 3].twin[side % 3];
            if (w.across >= 0) __builtin_prefetch(&face[w.across / 3]);
        };
        const auto begin_walk = [&](Walk& w) {
            while (pending < end && corners[pending] == 0) ++pending;
            w.v = pending < end ? pending++ : -1;
            if (w.v < 0) return;
            w.start = first[w.v], w.seen = 1, w.backwards = false;
            cross(w, prev(w.start));
        };
        const auto finish = [&](Walk& w) {
            bad[w.v] = w.seen != corners[w.v];
            begin_walk(w);
        };
        const auto end_leg = [&](Walk& w) {
            if (w.backwards) return finish(w);
            w.backwards = true;
            cross(w, next(w.start));
        };
        Walk lanes[kLanes];
        for (Walk& w : lanes) begin_walk(w);
        for (bool walking = true; walking;) {
            walking = false;
            for (Walk& w : lanes) {
                if (w.v < 0) continue;
                walking = true;
                const int across = w.across;
                if (w.seen > corners[w.v] || across < 0) {
                    end_leg(w);
                    continue;
                }
                const FaceRecord& r = face[across / 3];
                const int c = across - across % 3 + (r.vertex[0] == w.v ? 0 : r.vertex[1] == w.v ? 1 : 2);
                if (c == w.start) {  // back at the start: a closed fan
                    finish(w);
                    continue;
                }
                ++w.seen;
                cross(w, prev(c) == across ? next(c) : prev(c));
            }
        }
    }
    std::vector<int> result;
    for (int v = 0; v < num_vertices; ++v)
        if (bad[v]) result.push_back(v);
    return result;
}

}  // namespace

EdgeTable build_edge_table(const Eigen::MatrixX3i& F, int num_vertices, NonmanifoldVertices nonmanifold_vertices) {
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
    const std::unique_ptr<std::uint64_t[]> keys(new std::uint64_t[bucket_start.back()]);  // all written below
    detail::prefault(keys.get(), sizeof(std::uint64_t) * static_cast<size_t>(bucket_start.back()));
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

    // Sort each bucket and count its distinct upper endpoints (buckets are independent, so in
    // parallel); a prefix sum then gives every bucket the range of edge ids it numbers.
    std::vector<int> edge_start(static_cast<size_t>(num_vertices) + 1, 0);
    auto is_new_edge = [&keys](std::size_t i, std::size_t begin) { return i == begin || (keys[i] >> 32) != (keys[i - 1] >> 32); };
#pragma omp parallel for schedule(dynamic, 1024)
    for (int v = 0; v < num_vertices; ++v) {
        const std::size_t begin = bucket_start[v], end = bucket_start[v + 1];
        std::sort(keys.get() + begin, keys.get() + end);
        int count = 0;
        for (std::size_t i = begin; i < end; ++i) count += is_new_edge(i, begin);
        edge_start[v + 1] = count;
    }
    std::partial_sum(edge_start.begin(), edge_start.end(), edge_start.begin());
    const int num_edges = edge_start.back();

    EdgeTable table;
    table.face_edge = detail::prefaulted_constant<Eigen::MatrixX3i>(num_faces, 3, -1);
    table.E.resize(num_edges, 2);
    detail::prefault(table.E);
    table.edge_halfedges = detail::prefaulted_constant<Eigen::MatrixX2i>(num_edges, 2, -1);
    detail::prefaulted_assign(table.face_count, static_cast<std::size_t>(num_edges), 0);
#pragma omp parallel for schedule(dynamic, 1024)
    for (int v = 0; v < num_vertices; ++v) {
        const std::size_t begin = bucket_start[v], end = bucket_start[v + 1];
        int e = edge_start[v] - 1;
        for (std::size_t i = begin; i < end; ++i) {
            const int h = static_cast<int>(keys[i] & 0xffffffffu);
            if (is_new_edge(i, begin)) {
                ++e;
                table.E(e, 0) = v;
                table.E(e, 1) = static_cast<int>(keys[i] >> 32);
            }
            table.face_edge(h / 3, h % 3) = e;
            const int rank = table.face_count[e]++;
            if (rank < 2) table.edge_halfedges(e, rank) = h;
        }
    }
    if (nonmanifold_vertices == NonmanifoldVertices::find)
        table.nonmanifold_vertices = find_nonmanifold_vertices(F, table, valid_face, num_vertices);
    return table;
}

}  // namespace sdmesh
