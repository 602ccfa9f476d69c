#pragma once
/// \file ArgCursor: the benchmarks' command-line walk — each flag, and the value after it, with a clear exit
/// (status 2) when a value is missing.

#include <cstdio>
#include <cstdlib>
#include <string>

namespace cdbench {

class ArgCursor {
public:
    ArgCursor(int argc, char** argv) noexcept : argc_(argc), argv_(argv) {}
    /// Steps to the next argument; false after the last one.
    [[nodiscard]] bool next() noexcept { return ++i_ < argc_; }
    /// The current argument.
    [[nodiscard]] std::string flag() const { return argv_[i_]; }
    /// Consumes and returns the argument after the current flag; exits with status 2 when there is none.
    [[nodiscard]] std::string value() {
        if (i_ + 1 >= argc_) {
            std::fprintf(stderr, "%s needs a value\n", argv_[i_]);
            std::exit(2);
        }
        return argv_[++i_];
    }

private:
    int argc_;
    char** argv_;
    int i_ = 0;
};

}  // namespace cdbench
