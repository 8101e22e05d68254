// Decimation quality table (issue #5): every manifold corpus mesh converted to self-Delaunay
// (split), then decimated to 50%, 20% and 10% of its vertices by sdmesh::decimate and, to the
// same vertex count, by OpenMesh's quadric decimater (ModQuadric, no error bound) — the
// unconstrained reference. Both outputs are measured against the converted mesh (two-sided
// sampled Hausdorff relative to its bounding-box diagonal); the reference's certificate counts
// the edges that are not locally Delaunay, the problem sdmesh::decimate avoids. A third run
// without the fallback candidates (search_candidates = false) measures whether they reach further.
//   decimation_table --out DIR [--corpus DIR] [--quick] [--mesh NAME]
// --mesh runs one corpus mesh, also one of the large ones left out of the default list.
// Writes DIR/decimation.csv and DIR/decimation.md. OpenMesh is used here only, as the reference.
// Exit status: 0 done, 1 a mesh failed (an error, an output not self-Delaunay or with another
// topology, or a Hausdorff distance at 20 % above 1.5x the reference's), 2 bad usage.

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "sdmesh/convert.hpp"
#include "sdmesh/decimate.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"
#include "study.hpp"

namespace fs = std::filesystem;

namespace {


// The manifold meshes of the corpus (the two non-manifold ones and the LARGE derived ones are
// left out); --quick keeps the first three (boot: the closest to the target ratio).
const std::vector<std::string> kMeshes = {
    "npm_bunny.obj", "cgal_mushroom.off", "oded_boot.obj",     "cgal_elk.off",      "cgal_couplingdown.off",
    "cgal_cheese.off", "oded_spot.obj",   "oded_mountain.obj", "c3d_nefertiti.obj", "oded_koala.obj",
};
constexpr size_t kQuickMeshes = 3;
constexpr double kRatios[] = {0.5, 0.2, 0.1};
// Issue #5: at 20 % of the vertices, our Hausdorff distance is at most this times the reference's.
constexpr double kTargetRatio = 1.5;

struct DoubleTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using ReferenceMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh's quadric decimater down to `vertices` vertices.
sdmesh::TriangleMesh reference_decimate(const sdmesh::TriangleMesh& mesh, long long vertices) {
    ReferenceMesh om;
    std::vector<ReferenceMesh::VertexHandle> handle;
    for (int v = 0; v < mesh.num_vertices(); ++v)
        handle.push_back(om.add_vertex({mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2)}));
    for (int f = 0; f < mesh.num_faces(); ++f) om.add_face(handle[mesh.F(f, 0)], handle[mesh.F(f, 1)], handle[mesh.F(f, 2)]);
    OpenMesh::Decimater::DecimaterT<ReferenceMesh> decimater(om);
    OpenMesh::Decimater::ModQuadricT<ReferenceMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();
    decimater.initialize();
    decimater.decimate_to(static_cast<size_t>(vertices));
    om.garbage_collection();
    sdmesh::TriangleMesh out;
    out.V.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
    for (const auto v : om.vertices()) {
        const auto& p = om.point(v);
        out.V.row(v.idx()) << p[0], p[1], p[2];
    }
    out.F.resize(static_cast<Eigen::Index>(om.n_faces()), 3);
    for (const auto f : om.faces()) {
        int k = 0;
        for (const auto v : om.fv_range(f)) out.F(f.idx(), k++) = v.idx();
    }
    return out;
}

struct Row {
    std::string mesh;
    long long converted_vertices = 0;
    double ratio = 0;
    long long target = 0, ours_vertices = 0, region_only_vertices = 0;
    std::string status = {}, region_only_status = {};
    bool ours_self_delaunay = false, topology_kept = false;
    double ours_hausdorff = 0, reference_hausdorff = 0;
    long long reference_non_delaunay = 0, reference_interior_edges = 0;
    double ours_seconds = 0;
};

bool same_topology(const sdmesh::MeshInfo& a, const sdmesh::MeshInfo& b) {
    return b.manifold() && a.genus == b.genus && a.boundary_loops == b.boundary_loops && a.components == b.components;
}

std::vector<Row> measure(const fs::path& path) {
    const sdmesh::TriangleMesh converted = sdmesh::convert(sdmesh::read_mesh(path)).mesh;
    const sdmesh::MeshInfo info = sdmesh::validate(converted);
    std::vector<Row> rows;
    for (const double ratio : kRatios) {
        Row row{.mesh = path.filename().string(), .converted_vertices = converted.num_vertices(), .ratio = ratio};
        const sdmesh::DecimateResult ours = sdmesh::decimate(converted, {.target_ratio = ratio, .measure_hausdorff = false});
        const sdmesh::DecimateReport region_only =
            sdmesh::decimate(converted, {.target_ratio = ratio, .search_candidates = false, .measure_hausdorff = false})
                .report;
        // The reference goes to the count ours reached (the target unless ours stalled).
        const sdmesh::TriangleMesh reference = reference_decimate(converted, ours.report.output_vertices);
        const sdmesh::DelaunayCertificate reference_cert = sdmesh::certify(reference);
        row.target = ours.report.target_vertices;
        row.ours_vertices = ours.report.output_vertices;
        row.status = sdmesh::to_string(ours.report.status);
        row.region_only_vertices = region_only.output_vertices;
        row.region_only_status = sdmesh::to_string(region_only.status);
        row.ours_self_delaunay = ours.report.certificate.self_delaunay;
        row.topology_kept = same_topology(info, sdmesh::validate(ours.mesh));
        row.ours_seconds = ours.report.seconds;
        row.ours_hausdorff = sdmesh::hausdorff_distance(converted, ours.mesh).hausdorff_rel;
        row.reference_hausdorff = sdmesh::hausdorff_distance(converted, reference).hausdorff_rel;
        row.reference_non_delaunay = reference_cert.non_delaunay_edges;
        row.reference_interior_edges = reference_cert.interior_edges;
        rows.push_back(row);
        std::cerr << row.mesh << " " << ratio << ": ours " << row.ours_hausdorff << " (" << row.status << "), reference "
                  << row.reference_hausdorff << "\n";
    }
    return rows;
}

// ours / reference, or a dash where the reference is exact (it removed only vertices that the
// conversion had put on the surface's edges and faces).
std::string hausdorff_ratio(const Row& r) {
    if (r.reference_hausdorff <= 1e-12) return "—";
    std::ostringstream out;
    out << std::setprecision(3) << r.ours_hausdorff / r.reference_hausdorff;
    return out.str();
}

std::string percent(double ratio) { return std::to_string(static_cast<int>(ratio * 100 + 0.5)) + "%"; }

void write_csv(const fs::path& file, const std::vector<Row>& rows) {
    std::ostringstream out;
    out << std::setprecision(6)
        << "mesh,converted_vertices,ratio,target,ours_vertices,status,ours_self_delaunay,topology_kept,ours_hausdorff_rel,"
           "reference_hausdorff_rel,hausdorff_ratio,reference_non_delaunay_edges,reference_interior_edges,"
           "region_only_vertices,region_only_status,ours_seconds\n";
    for (const Row& r : rows)
        out << r.mesh << ',' << r.converted_vertices << ',' << r.ratio << ',' << r.target << ',' << r.ours_vertices << ','
            << r.status << ',' << r.ours_self_delaunay << ',' << r.topology_kept << ',' << r.ours_hausdorff << ','
            << r.reference_hausdorff << ',' << r.ours_hausdorff / r.reference_hausdorff << ',' << r.reference_non_delaunay
            << ',' << r.reference_interior_edges << ',' << r.region_only_vertices << ',' << r.region_only_status << ','
            << r.ours_seconds << '\n';
    sdmesh::write_text_file(file, out.str());
}

void write_markdown(const fs::path& file, const std::vector<Row>& rows) {
    std::ostringstream out;
    out << std::setprecision(3)
        << "# Decimation: sdmesh::decimate vs OpenMesh's quadric decimater\n\n"
           "Each manifold corpus mesh is converted (split) to self-Delaunay, then decimated to the target\n"
           "fraction of its vertices. Hausdorff: two-sided, sampled, relative to the converted mesh's\n"
           "bounding-box diagonal. `ratio` = ours / reference (target ≤ 1.5 at 20%). `ref. non-LD` = interior\n"
           "edges of the reference output that are not locally Delaunay. `region only` = vertices reached\n"
           "without the fallback candidates. `ours s`: wall-clock seconds of sdmesh::decimate (shared\n"
           "machine). Generated by experiments/decimation/decimation_table.\n\n"
           "| mesh | V (converted) | target | ours V | status | self-Delaunay, topology | ours H | reference H | ratio | "
           "ref. non-LD | region only V | ours s |\n"
           "|---|---:|---:|---:|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : rows)
        out << "| `" << r.mesh << "` | " << r.converted_vertices << " | " << percent(r.ratio) << " (" << r.target << ") | "
            << r.ours_vertices << " | " << r.status << " | " << (r.ours_self_delaunay ? "yes" : "NO") << ", "
            << (r.topology_kept ? "kept" : "CHANGED") << " | " << r.ours_hausdorff << " | " << r.reference_hausdorff
            << " | " << hausdorff_ratio(r) << " | " << r.reference_non_delaunay << " / "
            << r.reference_interior_edges << " | " << r.region_only_vertices << " | " << r.ours_seconds << " |\n";
    sdmesh::write_text_file(file, out.str());
}

}  // namespace

int main(int argc, char** argv) {
    const study::Args args = study::parse_args(argc, argv, "decimation_table");
    const fs::path& out = args.out;
    const fs::path& corpus = args.corpus;
    const bool quick = args.quick;
    const std::string& only = args.mesh;
    fs::create_directories(out);
    std::vector<Row> rows;
    int failed = 0;
    // --mesh names any corpus mesh, the large ones too.
    const std::vector<std::string> names =
        !only.empty() ? std::vector<std::string>{only}
                      : std::vector<std::string>(kMeshes.begin(), kMeshes.begin() + (quick ? kQuickMeshes : kMeshes.size()));
    for (const std::string& name : names) {
        try {
            const std::vector<Row> mesh_rows = measure(corpus / name);
            rows.insert(rows.end(), mesh_rows.begin(), mesh_rows.end());
        } catch (const std::exception& e) {
            std::cerr << "decimation_table: " << name << ": " << e.what() << "\n";
            ++failed;
        }
    }
    for (const Row& r : rows) {
        const bool over = r.ratio == 0.2 && r.ours_hausdorff > kTargetRatio * r.reference_hausdorff;
        if (r.ours_self_delaunay && r.topology_kept && !over) continue;
        std::cerr << "decimation_table: " << r.mesh << " at " << percent(r.ratio) << ": "
                  << (!r.ours_self_delaunay ? "not self-Delaunay"
                      : !r.topology_kept    ? "topology changed"
                                            : "Hausdorff " + hausdorff_ratio(r) + "x the reference's, above " +
                                                  std::to_string(kTargetRatio).substr(0, 3))
                  << "\n";
        ++failed;
    }
    write_csv(out / "decimation.csv", rows);
    write_markdown(out / "decimation.md", rows);
    return failed > 0 ? 1 : 0;
}
