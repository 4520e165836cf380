#pragma once
// Expected<T>: a value or an Error, for bad input and missing devices (STYLE.md rule 7).
// The message names the file and the place in it; callers add context with withContext().
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/check.h"

namespace daisy {

struct Error {
    std::string message;
};

template <typename T>
class [[nodiscard]] Expected {
public:
    Expected(T value) : state_(std::in_place_index<0>, std::move(value)) {}
    Expected(Error error) : state_(std::in_place_index<1>, std::move(error)) {}

    bool ok() const { return state_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & {
        DAISY_CHECK(ok());
        return std::get<0>(state_);
    }
    const T& value() const& {
        DAISY_CHECK(ok());
        return std::get<0>(state_);
    }
    T&& value() && {
        DAISY_CHECK(ok());
        return std::get<0>(std::move(state_));
    }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

    const Error& error() const {
        DAISY_CHECK(!ok());
        return std::get<1>(state_);
    }

private:
    std::variant<T, Error> state_;
};

template <>
class [[nodiscard]] Expected<void> {
public:
    Expected() = default;
    Expected(Error error) : error_(std::move(error)), ok_(false) {}

    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    const Error& error() const {
        DAISY_CHECK(!ok_);
        return error_;
    }

private:
    Error error_;
    bool ok_ = true;
};

// Prefixes an error message with context, e.g. withContext(e, "scene.gltf") -> "scene.gltf: ...".
inline Error withContext(const Error& error, const std::string& context) {
    return Error{context + ": " + error.message};
}

}  // namespace daisy
