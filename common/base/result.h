// Result<T>: a value or an Error, for expected failures (input, I/O, network, backends).
// libstdc++ 12 has no std::expected in C++20 mode, hence this small type (STYLE.md §5.2).
#pragma once

#include <string>
#include <utility>
#include <variant>

#include <fmt/format.h>

namespace pathfarm {

enum class ErrorCode {
    invalid_argument,  // a flag or parameter is out of range
    not_found,         // a file, scene, texture or device does not exist
    parse_error,       // a file exists but its content is malformed or truncated
    unsupported,       // valid input that this build cannot handle
    io_error,          // reading or writing failed
    backend_error,     // Embree / OpenCL reported a failure
};

// One line naming the input and the problem, e.g. "scene.gltf: mesh 3: 12 NaN positions".
struct Error {
    ErrorCode code = ErrorCode::invalid_argument;
    std::string message;
};

template <typename... Args>
Error make_error(ErrorCode code, fmt::format_string<Args...> format, Args&&... args) {
    return Error{code, fmt::format(format, std::forward<Args>(args)...)};
}

template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : data_(std::move(value)) {}
    Result(Error error) : data_(std::move(error)) {}

    bool ok() const { return data_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<0>(data_); }
    const T& value() const& { return std::get<0>(data_); }
    T&& value() && { return std::get<0>(std::move(data_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T&& operator*() && { return std::move(*this).value(); }

    const Error& error() const { return std::get<1>(data_); }

private:
    std::variant<T, Error> data_;
};

// Result<void>: success or an Error.
template <>
class [[nodiscard]] Result<void> {
public:
    Result() = default;
    Result(Error error) : error_(std::move(error)), ok_(false) {}

    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    const Error& error() const { return error_; }

private:
    Error error_;
    bool ok_ = true;
};

using Status = Result<void>;

}  // namespace pathfarm
