#pragma once
// JSON forms of the library's reports, shared by the commands that print them.

#include "cli/json.hpp"
#include "sdmesh/delaunay.hpp"

namespace sdmesh::cli {

/// The certificate's counts and verdict (the keys of `sdmesh check --json` that concern it).
JsonObject certificate_json(const DelaunayCertificate& cert, const CertifyOptions& options);

}  // namespace sdmesh::cli
