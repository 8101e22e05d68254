// `sdmesh repair IN OUT`: the safe repairs of validate.hpp, none of which moves a vertex by more than
// rounding or a needle's short side.

#include <iostream>

#include "cli/commands.hpp"
#include "cli/json.hpp"
#include "cli/reports.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::cli {

int run_repair(Args& args) {
    RepairOptions options;
    options.merge_coincident_vertices = !args.flag("--keep-coincident");
    options.collapse_needles = !args.flag("--keep-needles");
    options.drop_repeated_index_faces = !args.flag("--keep-repeated");
    options.drop_duplicate_faces = !args.flag("--keep-duplicates");
    options.split_nonmanifold_vertices = !args.flag("--keep-nonmanifold");
    options.orient = !args.flag("--keep-orientation");
    options.flip_caps = !args.flag("--keep-caps");
    options.drop_unreferenced_vertices = !args.flag("--keep-unreferenced");
    const auto paths = args.positionals(
        2, "sdmesh repair IN OUT [--keep-coincident] [--keep-needles] [--keep-repeated] "
           "[--keep-duplicates] [--keep-nonmanifold] [--keep-orientation] [--keep-caps] [--keep-unreferenced]");

    const TriangleMesh mesh = read_mesh(paths[0]);
    check_mesh_output(paths[1]);
    RepairReport report;
    const TriangleMesh repaired = about_file(paths[0], [&] { return repair(mesh, options, &report); });
    const MeshInfo info = validate(repaired);
    write_mesh(paths[1], repaired);

    JsonObject out;
    out.add("input", paths[0]).add("output", paths[1]).merge(repair_json(report, info));
    std::cout << out.str() << '\n';
    if (const std::string defect = first_defect(info); !defect.empty())
        std::cerr << "sdmesh repair: " << paths[1] << " is still not a manifold: " << defect << '\n';
    return kSuccess;
}

}  // namespace sdmesh::cli
