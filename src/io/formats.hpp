#pragma once
// The per-format readers and writers behind read_mesh / parse_mesh / write_mesh (mesh_io.cpp).
//
// Readers get the whole decompressed file; `file` is the name used in error messages. They fill
// `report` except `format` and `compressed`, which mesh_io.cpp sets. Writers get a mesh that
// mesh_io.cpp has already validated (face indices in range, fields well-formed).

#include <span>
#include <string_view>

#include "io/output_file.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh::io {

TriangleMesh parse_obj(std::string_view text, std::string_view file, ReadReport& report);
TriangleMesh parse_off(std::string_view text, std::string_view file, ReadReport& report);
TriangleMesh parse_ply(std::string_view bytes, std::string_view file, ReadReport& report);
TriangleMesh parse_stl(std::string_view bytes, std::string_view file, ReadReport& report);

void write_obj(const TriangleMesh& mesh, OutputFile& out);
void write_off(const TriangleMesh& mesh, OutputFile& out);
void write_ply(const TriangleMesh& mesh, std::span<const VertexField> fields, bool ascii,
               OutputFile& out);

}  // namespace sdmesh::io
