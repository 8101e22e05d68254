#pragma once
// gzip through zlib, in memory: whole-buffer inflate for reading, a streaming encoder for writing.

#include <cstddef>
#include <string>
#include <string_view>

#include <zlib.h>

namespace sdmesh::io {

/// Decompresses gzip (or zlib) data, including files of several concatenated gzip members.
/// \throws ParseError "<file>: ..." for corrupt or truncated data.
/// \throws IoError "<file>: ..." if it decompresses to more than max_bytes (see memory_budget.hpp).
std::string gunzip(std::string_view compressed, std::string_view file, std::size_t max_bytes);

/// Streams data into gzip format.
class GzipEncoder {
public:
    GzipEncoder();
    ~GzipEncoder();
    GzipEncoder(const GzipEncoder&) = delete;
    GzipEncoder& operator=(const GzipEncoder&) = delete;

    /// Compresses `input` and appends the compressed bytes produced so far to `output`;
    /// `finish` ends the stream (its trailer is appended too).
    void compress(std::string_view input, bool finish, std::string& output);

private:
    z_stream stream_{};
};

}  // namespace sdmesh::io
