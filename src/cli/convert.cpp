// `sdmesh convert IN OUT`: any manifold mesh to a certified self-Delaunay mesh.

#include <iostream>
#include <limits>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "cli/json.hpp"
#include "cli/reports.hpp"
#include "cli/shared_options.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::cli {
namespace {

// Whether the defect that convert names (the first of require_oriented_manifold's) is of a kind
// the safe repairs mend. They leave non-finite coordinates and a non-orientable surface as they
// are, and an inconsistent orientation says so in its own message.
bool repair_may_mend(const MeshInfo& info) {
    if (info.non_finite_vertices > 0) return false;
    if (!first_defect(info).empty()) return true;  // non-manifold, repeated indices
    return info.orientable && info.orientation_conflicts == 0 && info.zero_area_faces > 0;
}

constexpr const char* kConvertUsage =
    "sdmesh convert IN OUT [--method split|hybrid|flip] [--split-rule interval|shell] [--max-dihedral DEG] "
    "[--coplanar-tolerance RAD] [--boundary strict|free] [--max-vertices N] [--tolerance RAD] [--cascade-trials N] "
    "[--local-search PASSES] [--lower-bound] [--repair] [--no-hausdorff] [--report FILE.json] [--progress]";

}  // namespace

int run_convert(Args& args) {
    ConvertOptions options;
    options.method = parse_method(args, "--method").value_or(options.method);
    options.split_rule = args.choice("--split-rule", {std::pair{"interval", SplitRule::interval},
                                                      std::pair{"shell", SplitRule::shell}})
                             .value_or(options.split_rule);
    options.boundary = parse_boundary(args).value_or(options.boundary);
    options.max_dihedral_deg = args.number("--max-dihedral").value_or(options.max_dihedral_deg);
    options.coplanar_tolerance = args.number("--coplanar-tolerance").value_or(options.coplanar_tolerance);
    options.tolerance = args.number("--tolerance").value_or(options.tolerance);
    // Vertex ids are ints.
    options.max_vertices = args.whole_number("--max-vertices", 0, std::numeric_limits<int>::max()).value_or(0);
    options.cascade_trials =
        static_cast<int>(args.whole_number("--cascade-trials", 0, 1000).value_or(options.cascade_trials));
    options.local_search = static_cast<int>(args.whole_number("--local-search", 0, 100).value_or(0));
    options.lower_bound = args.flag("--lower-bound");
    options.progress = args.flag("--progress");
    options.measure_hausdorff = !args.flag("--no-hausdorff");
    const bool repair_first = args.flag("--repair");
    const std::optional<std::string> report_path = args.option("--report");
    const auto paths = args.positionals(2, kConvertUsage);

    if (options.progress) std::cerr << "convert: reading " << paths[0] << std::endl;
    TriangleMesh mesh = read_mesh(paths[0]);
    check_mesh_output(paths[1]);  // before the conversion, not after it
    if (report_path) check_text_output(*report_path);
    if (repair_first) mesh = about_file(paths[0], [&] { return repair(mesh); });
    const ConversionResult result = about_file(paths[0], [&] {
        try {
            return convert(mesh, options);
        } catch (const InvalidMeshError& e) {
            if (repair_first || !repair_may_mend(validate(mesh))) throw;
            throw InvalidMeshError(std::string(e.what()) + " (--repair mends what it safely can)");
        }
    });
    if (options.progress) std::cerr << "convert: writing " << paths[1] << std::endl;
    write_mesh(paths[1], result.mesh);

    const ConversionReport& r = result.report;
    JsonObject json;
    json.add("input", paths[0])
        .add("output", paths[1])
        .merge(conversion_json(options, result.report));
    const std::string text = json.str() + "\n";
    if (report_path) write_text_file(*report_path, text);
    std::cout << text;
    if (r.status == ConvertStatus::budget_exhausted) {
        // Thin strips of faces beside a fold need points about as far apart as the strip is wide,
        // whatever the rule (experiments/README.md): flipping nearly flat folds avoids most of them.
        const char* instead = options.method == ConvertMethod::split
                                  ? ", --coplanar-tolerance flips between faces that a file's rounding bent off one "
                                    "plane, and --method hybrid flips nearly flat folds instead of splitting them"
                              : options.method == ConvertMethod::hybrid
                                  ? ", and a larger --max-dihedral flips more folds instead of splitting them"
                                  : "";
        std::cerr << "sdmesh convert: " << paths[1] << ": not certified (budget_exhausted at " << r.output_vertices
                  << " vertices and " << r.flips << " flips, " << r.certificate.non_delaunay_edges
                  << " non-Delaunay edges left; faces with angles near 0 or 180 degrees can need many vertices: "
                     "--max-vertices sets the vertex budget"
                  << instead << ")\n";
    }
    else if (r.status != ConvertStatus::certified) {
        std::string rest = options.method == ConvertMethod::flip
                               ? "that flips cannot fix; --method split certifies"
                               : "left; --method hybrid or --repair may help";
        if (r.skipped_splits > 0)
            rest = "left, " + std::to_string(r.skipped_splits) +
                   " splits skipped where the point fell on a vertex in double precision; " +
                   (options.method == ConvertMethod::hybrid ? "a larger --max-dihedral" : "--method hybrid") +
                   " may help";
        std::cerr << "sdmesh convert: " << paths[1] << ": not certified (" << to_string(r.status) << ", "
                  << r.certificate.non_delaunay_edges << " non-Delaunay edges and "
                  << r.certificate.boundary_obtuse_edges << " obtuse boundary edges " << rest << ")\n";
    }
    return r.status == ConvertStatus::certified ? kSuccess : kFellShort;
}

}  // namespace sdmesh::cli
