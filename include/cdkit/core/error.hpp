#pragma once
/// \file The one exception type for bad data from outside, and the precondition assert.
///
/// Policy: data that comes from outside (files, user meshes, user transforms at build time) is checked
/// where it enters and raises `cdkit::Error`. Query paths are `noexcept` and never throw; their
/// preconditions are checked with `CDKIT_ASSERT`, whose handler the application may replace.

#include <stdexcept>
#include <string>

namespace cdkit {

/// Raised for bad input: names the source (file path or "<memory>"/"<mesh>"), the element (e.g.
/// "vertex 17", "triangle 4") and the reason.
class Error : public std::runtime_error {
public:
    Error(std::string source, std::string element, std::string reason)
        : std::runtime_error(compose(source, element, reason)),
          source_(std::move(source)), element_(std::move(element)), reason_(std::move(reason)) {}

    [[nodiscard]] const std::string& source() const noexcept { return source_; }
    [[nodiscard]] const std::string& element() const noexcept { return element_; }
    [[nodiscard]] const std::string& reason() const noexcept { return reason_; }

private:
    static std::string compose(const std::string& s, const std::string& e, const std::string& r) {
        std::string m = s.empty() ? std::string("<input>") : s;
        if (!e.empty()) m += ": " + e;
        return m + ": " + r;
    }
    std::string source_, element_, reason_;
};

/// Called when a CDKIT_ASSERT fails. The default prints the message and aborts.
using AssertHandler = void (*)(const char* expr, const char* msg, const char* file, int line);

namespace detail {
[[noreturn]] void default_assert_handler(const char* expr, const char* msg, const char* file, int line);
AssertHandler& assert_handler_slot() noexcept;
}  // namespace detail

/// Replaces the assert handler; returns the previous one. Not thread-safe: set it at start-up.
AssertHandler set_assert_handler(AssertHandler h) noexcept;

}  // namespace cdkit

#if defined(CDKIT_DISABLE_ASSERTS)
#define CDKIT_ASSERT(cond, msg) ((void)0)
#else
#define CDKIT_ASSERT(cond, msg)                                                             \
    ((cond) ? (void)0 : ::cdkit::detail::assert_handler_slot()(#cond, (msg), __FILE__, __LINE__))
#endif
