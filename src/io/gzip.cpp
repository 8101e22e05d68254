// gzip reading and writing with zlib.

#include "io/gzip.hpp"

#include <algorithm>
#include <limits>
#include <new>
#include <stdexcept>

#include "io/memory_budget.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::io {
namespace {

// zlib counts in uInt; feed it at most this much per call.
constexpr std::size_t kMaxChunk = std::numeric_limits<uInt>::max() / 2;

uInt chunk_size(std::size_t bytes) { return static_cast<uInt>(std::min(bytes, kMaxChunk)); }

// A first guess of the decompressed size, to avoid regrowing a large buffer: the size the gzip
// trailer stores (modulo 2^32). A truncated or corrupt file has garbage there, so the guess is
// capped at 64x the compressed size (meshes compress 3-5x); past that the buffer just grows.
std::size_t expected_size(std::string_view compressed) {
    const std::size_t n = compressed.size();
    if (n < 18) return 4096;
    const auto* tail = reinterpret_cast<const unsigned char*>(compressed.data() + n - 4);
    const std::size_t isize = std::size_t{tail[0]} | std::size_t{tail[1]} << 8 |
                              std::size_t{tail[2]} << 16 | std::size_t{tail[3]} << 24;
    return std::clamp(isize, n, 64 * n);
}

[[noreturn]] void throw_corrupt(std::string_view file, const z_stream& stream) {
    throw ParseError(std::string(file) + ": corrupt gzip data (" +
                     (stream.msg != nullptr ? stream.msg : "unexpected end of data") + ")");
}

}  // namespace

std::string gunzip(std::string_view compressed, std::string_view file, std::size_t max_bytes) {
    z_stream stream{};
    // 15 + 32: the largest window, and detect the gzip or zlib header by itself.
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw ParseError(std::string(file) + ": zlib init failed");
    struct Guard {
        z_stream* s;
        ~Guard() { inflateEnd(s); }
    } guard{&stream};

    // One byte more than allowed tells data of exactly max_bytes from more.
    const std::size_t cap = max_bytes + 1;
    std::string out(std::min(expected_size(compressed), cap), '\0');
    std::size_t produced = 0;
    auto next_in = reinterpret_cast<const Bytef*>(compressed.data());
    std::size_t left_in = compressed.size();
    for (;;) {
        if (produced == out.size()) out.resize(std::min(2 * out.size(), cap));
        stream.next_in = const_cast<Bytef*>(next_in);  // zlib's API is not const-correct
        stream.avail_in = chunk_size(left_in);
        stream.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
        stream.avail_out = chunk_size(out.size() - produced);
        const uInt in_before = stream.avail_in;
        const uInt out_before = stream.avail_out;
        const int status = inflate(&stream, Z_NO_FLUSH);
        next_in += in_before - stream.avail_in;
        left_in -= in_before - stream.avail_in;
        produced += out_before - stream.avail_out;
        if (produced > max_bytes) throw_too_large(file, "decompresses to", MemoryUse::text, max_bytes);

        if (status == Z_STREAM_END) {
            // Concatenated gzip members form one file, and zero bytes after the last member are
            // padding (tape blocks), as gzip -d and Python's gzip module treat them.
            const std::string_view rest(reinterpret_cast<const char*>(next_in), left_in);
            if (rest.find_first_not_of('\0') == std::string_view::npos) break;
            if (inflateReset(&stream) != Z_OK) throw_corrupt(file, stream);
        } else if (status == Z_BUF_ERROR && left_in == 0 && stream.avail_out != 0) {
            throw_corrupt(file, stream);  // truncated: input ended inside the stream
        } else if (status != Z_OK && status != Z_BUF_ERROR) {
            throw_corrupt(file, stream);
        }
    }
    out.resize(produced);
    return out;
}

GzipEncoder::GzipEncoder() {
    // 15 + 16: the largest window, with a gzip header and trailer. Level 1: on mesh files (17-digit
    // text, binary doubles) the default level 6 is 3-5x slower for files only 0-15% smaller.
    if (deflateInit2(&stream_, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8,
                     Z_DEFAULT_STRATEGY) != Z_OK) {
        throw std::bad_alloc();
    }
}

GzipEncoder::~GzipEncoder() { deflateEnd(&stream_); }

void GzipEncoder::compress(std::string_view input, bool finish, std::string& output) {
    constexpr std::size_t kOutChunk = 1 << 16;
    auto next_in = reinterpret_cast<const Bytef*>(input.data());
    std::size_t left_in = input.size();
    for (;;) {
        const uInt feed = chunk_size(left_in);
        const bool last_feed = feed == left_in;
        stream_.next_in = const_cast<Bytef*>(next_in);
        stream_.avail_in = feed;
        const int flush = finish && last_feed ? Z_FINISH : Z_NO_FLUSH;
        int status = Z_OK;
        do {  // run deflate until it has taken all input given and has no more output pending
            const std::size_t old_size = output.size();
            output.resize(old_size + kOutChunk);
            stream_.next_out = reinterpret_cast<Bytef*>(output.data() + old_size);
            stream_.avail_out = static_cast<uInt>(kOutChunk);
            status = deflate(&stream_, flush);
            if (status == Z_STREAM_ERROR) throw std::logic_error("deflate: inconsistent stream state");
            output.resize(output.size() - stream_.avail_out);
        } while (stream_.avail_out == 0 || (flush == Z_FINISH && status != Z_STREAM_END));
        next_in += feed;
        left_in -= feed;
        if (last_feed) return;
    }
}

}  // namespace sdmesh::io
