#pragma once
// The exceptions of ecoterra: Error (an internal failure or a broken budget), and below it
// InputError (bad input: exit code 2), IoError (a file that cannot be read or written) and
// CheckpointError (an InputError about a checkpoint). Messages name the file, the field and the
// value; callers add context as the error propagates ("while reading mf.h5: ...").
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

/// A checkpoint that is damaged, of another version, or does not belong to the scene resuming it
/// (another grid, other switches, other weather): bad input like any other (exit code 2).
class CheckpointError : public InputError {
public:
    using InputError::InputError;
};

/// A number as a short string for messages ("0.05", "1e-08"), as an ostream prints it.
std::string format_number(double v);
/// A count rounded to a whole number, its thousands separated by commas ("12,321").
std::string grouped(double n);

/// Runs `f`; an ecoterra error it throws is thrown on as the same class with "<context>: " before
/// its message, so a user reads what was being done ("data/ecosystems/x.json: species 'Birch':
/// ..."). Other exceptions pass unchanged.
template <class F>
decltype(auto) with_context(const std::string& context, F&& f) {
    try {
        return f();
    } catch (const CheckpointError& e) {
        throw CheckpointError(context + ": " + e.what());
    } catch (const InputError& e) {
        throw InputError(context + ": " + e.what());
    } catch (const IoError& e) {
        throw IoError(context + ": " + e.what());
    } catch (const Error& e) {
        throw Error(context + ": " + e.what());
    }
}

} // namespace ecoterra
