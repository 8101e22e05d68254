// `sdmesh info` and `sdmesh check`.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <numbers>

#include "cli/commands.hpp"
#include "cli/json.hpp"
#include "cli/reports.hpp"
#include "cli/shared_options.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::cli {
namespace {

// A mesh read from a file with its edges and validation, shared by info and check.
struct Inspection {
    ReadReport read;
    TriangleMesh mesh;
    EdgeTable edges;
    MeshInfo info;
};

Inspection inspect(const std::string& path) {
    Inspection in;
    in.mesh = read_mesh(path, &in.read);
    about_file(path, [&] {
        require_indices_in_range(in.mesh);
        in.edges = build_edge_table(in.mesh.F, in.mesh.num_vertices());
        in.info = validate(in.mesh, in.edges);
    });
    return in;
}

}  // namespace

int run_info(Args& args) {
    const auto path = args.positionals(1, "sdmesh info MESH")[0];
    const Inspection in = inspect(path);
    const MeshInfo& i = in.info;
    std::printf("%s\n", path.c_str());
    std::printf("  faces in file       %lld (%lld polygons -> %lld triangles, %lld of them ear clipped)\n",
                in.read.file_faces, in.read.polygons, in.read.polygon_triangles, in.read.ear_clipped_polygons);
    if (in.read.skipped_line_faces > 0) {
        std::printf("  skipped             %lld faces of 1 or 2 corners (points and lines)\n",
                    in.read.skipped_line_faces);
    }
    std::printf("  vertices            %d referenced, %d unreferenced, %d non-finite, %d duplicate positions\n",
                i.vertices, i.unreferenced_vertices, i.non_finite_vertices, i.duplicate_vertex_positions);
    std::printf("  faces               %d (%d repeated index, %d zero area, %d duplicates)\n", i.faces,
                i.repeated_index_faces, i.zero_area_faces, i.duplicate_faces);
    std::printf("  edges               %d (%d interior, %d boundary, %d non-manifold)\n", i.edges,
                i.interior_edges, i.boundary_edges, i.nonmanifold_edges);
    std::printf("  non-manifold verts  %d\n", i.nonmanifold_vertices);
    std::printf("  components          %d\n", i.components);
    std::printf("  boundary loops      %d\n", i.boundary_loops);
    std::printf("  Euler char.         %d\n", i.euler_characteristic);
    if (i.genus >= 0) std::printf("  genus               %d\n", i.genus);
    else std::printf("  genus               undefined (not an orientable manifold)\n");
    std::printf("  orientation         %s, %d conflicting edges\n", i.orientable ? "orientable" : "NOT orientable",
                i.orientation_conflicts);
    std::printf("  manifold            %s\n", i.manifold() ? "yes" : "no");
    return kSuccess;
}

int run_check(Args& args) {
    const auto usage = "sdmesh check MESH [--json] [--boundary strict|free] [--tolerance RAD]";
    const bool json = args.flag("--json");
    CertifyOptions options;
    options.boundary = parse_boundary(args).value_or(BoundaryPolicy::strict);
    options.tolerance = args.number("--tolerance").value_or(kDelaunayTolerance);
    const auto path = args.positionals(1, usage)[0];

    const auto start = std::chrono::steady_clock::now();
    const Inspection in = inspect(path);
    const DelaunayCertificate cert = about_file(path, [&] { return certify(in.mesh, in.edges, options); });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double fraction =
        cert.interior_edges > 0 ? double(cert.non_delaunay_edges) / cert.interior_edges : 0.0;

    if (json) {
        JsonObject out;
        out.add("file", path)
            .merge(mesh_info_json(in.info))
            .merge(read_report_json(in.read))
            .merge(certificate_json(cert, options))
            .add("seconds", seconds);
        std::cout << out.str() << '\n';
    } else {
        std::printf("%s: %s\n", path.c_str(), cert.self_delaunay ? "self-Delaunay" : "NOT self-Delaunay");
        std::printf("  interior edges      %d, %d not locally Delaunay (%.4f%%)\n", cert.interior_edges,
                    cert.non_delaunay_edges, 100.0 * fraction);
        std::printf("  min margin          %.6g rad (%.6g deg)\n", cert.min_delaunay_margin,
                    cert.min_delaunay_margin * 180.0 / std::numbers::pi);
        std::printf("  boundary edges      %d, %d with an obtuse opposite angle (policy %s)\n",
                    cert.boundary_edges, cert.boundary_obtuse_edges, to_string(options.boundary).data());
        std::printf("  negative cotan w.   %d\n", cert.negative_cotan_weights);
        std::printf("  negative dual cells %d\n", cert.negative_dual_cells);
        std::printf("  Gabriel violations  %d\n", cert.gabriel_violations);
        std::printf("  collinear faces     %d (area 0: no angles)\n", cert.collinear_faces);
        if (!in.info.manifold())
            std::printf("  non-manifold        %d edges, %d vertices, %d faces with a repeated index\n",
                        in.info.nonmanifold_edges, in.info.nonmanifold_vertices, in.info.repeated_index_faces);
    }
    if (const std::string defect = first_defect(in.info); !defect.empty())
        std::cerr << "sdmesh check: " << path << ": not self-Delaunay: " << defect << '\n';
    return cert.self_delaunay ? kSuccess : kFellShort;
}

}  // namespace sdmesh::cli
