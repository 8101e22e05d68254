// Writes the seed corpus of the fuzz targets into a folder: small meshes (closed, open, sheared so
// that conversion has work to do) in every format sdmesh writes, gzipped or not, plus STL and a
// few hand-written files for the syntax the writers never produce. Each seed is the selector byte
// of fuzz_input.hpp followed by the file's bytes. Usage: make_seeds DIR

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "sdmesh/shapes.hpp"

namespace {

namespace fs = std::filesystem;
using sdmesh::MeshFormat;

void write_seed(const fs::path& dir, const std::string& name, MeshFormat format, bool gzip,
                const std::string& content) {
    std::ofstream out(dir / name, std::ios::binary);
    out.put(static_cast<char>(sdmesh::fuzz::selector(format, gzip)));
    out << content;
    if (!out) throw std::runtime_error("cannot write seed " + (dir / name).string());
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string binary_stl(const sdmesh::TriangleMesh& mesh) {
    std::string bytes(80, ' ');
    const auto append = [&bytes](const void* value, std::size_t n) {
        bytes.append(static_cast<const char*>(value), n);  // the host is little endian, like STL
    };
    const auto faces = static_cast<std::uint32_t>(mesh.num_faces());
    append(&faces, 4);
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const float normal[3] = {0, 0, 0};
        append(normal, sizeof normal);
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) {
                const auto x = static_cast<float>(mesh.V(mesh.F(f, k), c));
                append(&x, 4);
            }
        }
        const std::uint16_t attributes = 0;
        append(&attributes, 2);
    }
    return bytes;
}

std::string ascii_stl(const sdmesh::TriangleMesh& mesh) {
    std::string text = "solid seed\n";
    for (int f = 0; f < mesh.num_faces(); ++f) {
        text += " facet normal 0 0 0\n  outer loop\n";
        for (int k = 0; k < 3; ++k) {
            const auto v = mesh.V.row(mesh.F(f, k));
            text += "   vertex " + std::to_string(v(0)) + " " + std::to_string(v(1)) + " " +
                    std::to_string(v(2)) + "\n";
        }
        text += "  endloop\n endfacet\n";
    }
    return text + "endsolid seed\n";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: make_seeds DIR\n";
        return 2;
    }
    const fs::path dir = argv[1];
    fs::create_directories(dir);
    const std::vector<std::pair<std::string, sdmesh::TriangleMesh>> meshes = {
        {"icosphere", sdmesh::make_icosphere(0)},
        {"grid", sdmesh::make_grid(3, 3)},
        {"sheared_grid", sdmesh::make_grid(4, 2, 1.0, 1.0, 2.5)},
        {"cylinder", sdmesh::make_cylinder(6, 2, 1.0, 3.0)},
    };
    const std::pair<const char*, MeshFormat> written[] = {
        {".obj", MeshFormat::obj}, {".off", MeshFormat::off}, {".ply", MeshFormat::ply}};
    const fs::path scratch = dir / "scratch";
    for (const auto& [name, mesh] : meshes) {
        for (const auto& [extension, format] : written) {
            for (const bool gzip : {false, true}) {
                const fs::path file = scratch.string() + extension + (gzip ? ".gz" : "");
                sdmesh::write_mesh(file, mesh);
                write_seed(dir, name + extension + (gzip ? ".gz" : ""), format, gzip, file_bytes(file));
                fs::remove(file);
            }
        }
        const fs::path ascii_ply = scratch.string() + ".ply";
        sdmesh::write_mesh(ascii_ply, mesh, {.ply_ascii = true});
        write_seed(dir, name + ".ascii.ply", MeshFormat::ply, false, file_bytes(ascii_ply));
        fs::remove(ascii_ply);
        write_seed(dir, name + ".stl", MeshFormat::stl, false, binary_stl(mesh));
        write_seed(dir, name + ".ascii.stl", MeshFormat::stl, false, ascii_stl(mesh));
    }
    // Syntax the writers do not produce: polygons, relative and v/vt/vn corners, comments, counts
    // on their own line, colors, big-endian PLY with list-valued and unknown elements.
    write_seed(dir, "syntax.obj", MeshFormat::obj, false,
               "# quad and relative indices\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\n"
               "f 1/1/1 2/1/1 3/1/1 4/1/1\nv 0.5 0.5 1\nf -1 -4 -5\nfo 5 3 \\\n 4\ng x\ns off\n");
    write_seed(dir, "syntax.off", MeshFormat::off, false,
               "COFF\n# comment\n\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
               "1 1 0 1 1 1 1\n3 0 1 2 255 0 0\n3 2 1 3\n");
    std::string ply_be =
        "ply\nformat binary_big_endian 1.0\ncomment seed\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
        "property list uchar int vertex_indices\nelement edge 1\nproperty list ushort uint ids\n"
        "end_header\n";
    const unsigned char vertices[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7,      // (0,0,0) red 7
                                      0x3f, 0x80, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7,  // (1,0,0)
                                      0, 0, 0, 0, 0x3f, 0x80, 0, 0, 0, 0, 0, 0, 7,  // (0,1,0)
                                      3, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2,        // face 0 1 2
                                      0, 1, 0, 0, 0, 9};                            // edge list
    ply_be.append(reinterpret_cast<const char*>(vertices), sizeof vertices);
    write_seed(dir, "syntax_be.ply", MeshFormat::ply, false, ply_be);
    std::cout << "seeds written to " << dir << '\n';
    return 0;
}
