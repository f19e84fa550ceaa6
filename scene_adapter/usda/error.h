// SPDX-License-Identifier: Apache-2.0
// Exceptions thrown by the USDA reader. what() starts with "file:line:col: " when known.
#pragma once

#include <stdexcept>
#include <string>

#include "scene_adapter/usda/sourceLocation.h"

namespace principled::usd {

/// Every usd error. what() is "file:line:col: message" (or "file: message" without a line).
class Error : public std::runtime_error {
public:
    Error(SourceLocation where, const std::string& message)
        : std::runtime_error(where.file.empty() ? message : where.str() + ": " + message),
          _where(std::move(where)),
          _message(message) {}

    const SourceLocation& where() const { return _where; }
    /// The message without the location prefix.
    const std::string& message() const { return _message; }

private:
    SourceLocation _where;
    std::string _message;
};

/// A syntax error: what() is exactly "FILE:LINE:COL: expected X, found Y".
class ParseError : public Error {
public:
    using Error::Error;
};

}  // namespace principled::usd
