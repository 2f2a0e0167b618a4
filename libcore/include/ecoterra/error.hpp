#pragma once
// The one exception type of ecoterra. Messages name the file, the field and the value; callers
// add context as the error propagates ("while reading mf.h5: ...").
#include <stdexcept>
#include <string>

namespace ecoterra {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Bad input from a user: an option, a file or a value outside its valid range.
class InputError : public Error {
public:
    using Error::Error;
};

/// A file that cannot be read or written.
class IoError : public Error {
public:
    using Error::Error;
};

/// A number as a short string for messages ("0.05", "1e-08"), as an ostream prints it.
std::string format_number(double v);

/// Returns "<context>: <message>" for re-throwing with more context.
inline std::string with_context(const std::string& context, const std::exception& e) {
    return context + ": " + e.what();
}

} // namespace ecoterra
