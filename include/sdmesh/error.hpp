#pragma once
// Exceptions thrown by sdmesh. Every message says what went wrong and where (file, line, element).
//
// Bad input and bad arguments throw; expected numerical outcomes (a budget hit, a solver that did
// not converge) are a status in the returned report instead.

#include <stdexcept>
#include <string>

namespace sdmesh {

/// Base class of every exception sdmesh throws on purpose.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A file cannot be opened, read, written or renamed (missing, permissions, I/O failure).
class IoError : public Error {
public:
    using Error::Error;
};

/// The file's extension or header names a format sdmesh does not read or write.
class UnsupportedFormatError : public Error {
public:
    using Error::Error;
};

/// The file is of a supported format but its content is malformed (truncated, bad number,
/// face index out of range, ...).
class ParseError : public Error {
public:
    using Error::Error;
};

/// The mesh violates a precondition of the called algorithm (non-manifold edge, non-finite
/// coordinate, face with repeated vertices, ...).
class InvalidMeshError : public Error {
public:
    using Error::Error;
};

/// An argument or option is out of its documented range (k >= n, unknown option value, ...).
class InvalidArgumentError : public Error {
public:
    using Error::Error;
};

/// A numerical precondition fails (e.g. inverting a non-positive Hodge star entry).
class NumericalError : public Error {
public:
    using Error::Error;
};

}  // namespace sdmesh
