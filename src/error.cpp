#include "cdkit/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace cdkit {
namespace detail {
void default_assert_handler(const char* expr, const char* msg, const char* file, int line) {
    std::fprintf(stderr, "cdkit: assertion failed: %s (%s) at %s:%d\n", expr, msg, file, line);
    std::abort();
}
AssertHandler& assert_handler_slot() noexcept {
    static AssertHandler h = &default_assert_handler;
    return h;
}
}  // namespace detail

AssertHandler set_assert_handler(AssertHandler h) noexcept {
    AssertHandler old = detail::assert_handler_slot();
    detail::assert_handler_slot() = h ? h : &detail::default_assert_handler;
    return old;
}
}  // namespace cdkit
