#pragma once
// Buffered output to a new file, optionally gzip-compressed, with the number formatting the
// writers share: text doubles with 17 significant digits (enough to give back the same bits)
// and little-endian binary values.

#include <unistd.h>

#include <atomic>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "io/binary_reader.hpp"
#include "io/gzip.hpp"

namespace sdmesh::io {

class OutputFile {
public:
    /// Creates `path`, which must not exist yet. Errors name `name_for_errors` if given (the
    /// target of a temporary file), else `path`. \throws IoError
    OutputFile(const std::filesystem::path& path, bool gzip, std::string name_for_errors = {});
    /// Closes the file without reporting errors (the failure path; success calls close()).
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    void write(std::string_view bytes) {
        buffer_.append(bytes);
        if (buffer_.size() >= kFlushSize) flush(false);
    }
    void put(char c) { write(std::string_view(&c, 1)); }

    /// Shortest form up to 17 significant digits ("%.17g"): reading it back gives the same bits.
    void write_text(double value) {
        char text[32];
        auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::general, 17);
        write(std::string_view(text, static_cast<std::size_t>(result.ptr - text)));
    }
    void write_text(long long value) {
        char text[24];
        auto result = std::to_chars(text, text + sizeof text, value);
        write(std::string_view(text, static_cast<std::size_t>(result.ptr - text)));
    }

    template <class T>
    void write_little_endian(T value) {
        value = convert_byte_order(value, ByteOrder::little);
        char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        write(std::string_view(bytes, sizeof(T)));
    }

    /// Flushes everything, ends the gzip stream and closes the file. \throws IoError
    void close();

private:
    static constexpr std::size_t kFlushSize = std::size_t{1} << 20;
    void flush(bool finish);
    void write_raw(std::string_view bytes);

    std::string name_;  // for error messages
    std::FILE* file_ = nullptr;
    std::unique_ptr<GzipEncoder> gzip_;
    std::string buffer_;
    std::string compressed_;
};

/// The temporary files being written right now, so that an interrupted program (SIGINT, SIGTERM)
/// can remove them before it dies: the handler may only call async-signal-safe functions, hence
/// fixed slots of plain characters rather than a container.
class TemporaryFiles {
public:
    /// Records `path` (before the file is created); the slot to release, or -1 when every slot is
    /// taken or the path is too long (that file is then just not cleaned up on a signal).
    static int add(const std::filesystem::path& path) noexcept {
        const std::string& name = path.native();
        if (name.size() >= kMaxPath) return -1;
        for (int slot = 0; slot < kSlots; ++slot) {
            int expected = kFree;
            if (!state_[slot].compare_exchange_strong(expected, kFilling)) continue;
            std::memcpy(paths_[slot], name.c_str(), name.size() + 1);
            state_[slot].store(kInUse);
            return slot;
        }
        return -1;
    }
    /// Forgets a slot of add() (after the file was renamed or removed).
    static void release(int slot) noexcept {
        if (slot >= 0) state_[slot].store(kFree);
    }
    /// Removes every recorded file. Async-signal-safe: for signal handlers.
    static void remove_all() noexcept {
        for (int slot = 0; slot < kSlots; ++slot) {
            if (state_[slot].load() == kInUse) ::unlink(paths_[slot]);
        }
    }

private:
    static constexpr int kSlots = 64;  // files written at the same time
    static constexpr std::size_t kMaxPath = 4096;
    enum : int { kFree, kFilling, kInUse };
    static inline std::atomic<int> state_[kSlots] = {};
    static inline char paths_[kSlots][kMaxPath] = {};
};

/// Writes a file all at once or not at all: `write` fills an OutputFile on a temporary file in the
/// same folder (so the rename cannot cross file systems), which is then renamed over `path`. On any
/// failure the temporary is removed, `path` is left as it was and the exception propagates
/// (IoError for file-system failures).
void write_atomically(const std::filesystem::path& path, bool gzip,
                      const std::function<void(OutputFile&)>& write);

}  // namespace sdmesh::io
