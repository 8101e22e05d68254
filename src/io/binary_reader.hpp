#pragma once
// A bounds-checked cursor over binary data (binary PLY, binary STL) with a byte order.
//
// Every read checks the bytes left, so truncated or lying files end in a ParseError that names
// the record being read ("<file>: face 17: ..."), never in a read past the end. The caller sets
// that record with set_location() before reading it.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "io/errors.hpp"

namespace sdmesh::io {

enum class ByteOrder { little, big };

/// Reverses the bytes of an unsigned integer.
template <class U>
U byteswap(U value) {
    static_assert(std::is_unsigned_v<U>);
    std::uint64_t in = value;  // wide, so that the shifts need no integer promotion
    std::uint64_t out = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) {
        out = (out << 8) | (in & 0xFFu);
        in >>= 8;
    }
    return static_cast<U>(out);
}

/// The unsigned integer type as wide as T (the carrier for byte swapping).
template <class T>
using UnsignedOfSize = std::conditional_t<
    sizeof(T) == 1, std::uint8_t,
    std::conditional_t<sizeof(T) == 2, std::uint16_t,
                       std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;

/// Converts between the native byte order and `order` (the same operation both ways).
template <class T>
T convert_byte_order(T value, ByteOrder order) {
    constexpr ByteOrder native =
        std::endian::native == std::endian::little ? ByteOrder::little : ByteOrder::big;
    if constexpr (sizeof(T) == 1) {
        return value;
    } else {
        if (order == native) return value;
        using U = UnsignedOfSize<T>;
        return std::bit_cast<T>(byteswap(std::bit_cast<U>(value)));
    }
}

class BinaryReader {
public:
    BinaryReader(std::string_view data, ByteOrder order, std::string_view file)
        : pos_(data.data()), end_(data.data() + data.size()), order_(order), file_(file) {}

    [[nodiscard]] std::size_t remaining() const { return static_cast<std::size_t>(end_ - pos_); }

    /// Names the record being read, for error messages.
    void set_location(std::string_view element, long long index) {
        element_ = element;
        index_ = index;
    }

    template <class T>
    T read() {
        static_assert(std::is_arithmetic_v<T>);
        require(sizeof(T));
        T value;
        std::memcpy(&value, pos_, sizeof(T));
        pos_ += sizeof(T);
        return convert_byte_order(value, order_);
    }

    void skip(std::size_t bytes) {
        require(bytes);
        pos_ += bytes;
    }

    [[noreturn]] void fail(std::string_view what) const {
        throw_at_element(file_, element_, index_, what);
    }

private:
    void require(std::size_t bytes) const {
        if (remaining() < bytes) {
            fail("truncated: needs " + std::to_string(bytes) + " more bytes, only " +
                 std::to_string(remaining()) + " left in the file");
        }
    }

    const char* pos_;
    const char* end_;
    ByteOrder order_;
    std::string_view file_;
    std::string_view element_ = "header";
    long long index_ = 0;
};

}  // namespace sdmesh::io
