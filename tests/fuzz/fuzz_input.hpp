#pragma once
// How the fuzz targets read their input: the first byte chooses the mesh format (its low two bits)
// and whether the rest is gzip data (bit 2); the remaining bytes are the file's content. One
// mutated byte thus moves an input between readers, and the seed corpus covers every format.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/gzip.hpp"
#include "io/memory_budget.hpp"
#include "sdmesh/io.hpp"

namespace sdmesh::fuzz {

constexpr MeshFormat kFormats[] = {MeshFormat::obj, MeshFormat::off, MeshFormat::ply, MeshFormat::stl};
constexpr std::uint8_t kGzipBit = 4;

/// The selector byte for a format (and compression), as the seed generator writes it.
inline std::uint8_t selector(MeshFormat format, bool gzip) {
    std::uint8_t index = 0;
    while (kFormats[index] != format) ++index;
    return static_cast<std::uint8_t>(index | (gzip ? kGzipBit : 0));
}

/// Parses a fuzz input like read_mesh parses a file. \throws sdmesh::Error as read_mesh does.
inline TriangleMesh parse_fuzz_input(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return parse_mesh({}, MeshFormat::obj, "fuzz input");  // the empty-file error
    const MeshFormat format = kFormats[data[0] & 3];
    const std::string_view content(reinterpret_cast<const char*>(data + 1), size - 1);
    if ((data[0] & kGzipBit) == 0) return parse_mesh(content, format, "fuzz input");
    return parse_mesh(io::gunzip(content, "fuzz input", io::max_text_bytes()), format, "fuzz input");
}

}  // namespace sdmesh::fuzz
