#pragma once
// Provenance lines for a benchmark's CSV: what ran, where, built how. scripts/render-results prints them under
// every table rendered from the file. Needs CDKIT_SOURCE_DIR (the repository, for the commit).
#include <cstdio>
#include <string>

namespace cdbench {

/// The first line a shell command prints, trimmed ("?" when it prints nothing).
inline std::string first_line(const char* command) {
    std::string out;
    if (std::FILE* p = popen(command, "r")) {
        char buf[256];
        if (std::fgets(buf, sizeof buf, p)) out = buf;
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    while (!out.empty() && out.front() == ' ') out.erase(out.begin());
    return out.empty() ? "?" : out;
}

/// Provenance as comment lines, first in a CSV: command, machine, compiler, commit, date.
inline std::string provenance_lines(int argc, char** argv) {
    std::string command;
    for (int i = 0; i < argc; ++i) {  // appended in place: GCC 12 warned (-Wrestrict, a false positive) on " " + string
        if (i) command += ' ';
        command += argv[i];
    }
    return "# command: " + command + "\n# machine: " +
           first_line("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2") + "\n# compiler: " + __VERSION__ +
           "\n# commit: " + first_line("git -C " CDKIT_SOURCE_DIR " rev-parse --short HEAD") +
           "\n# date: " + first_line("date -u +%Y-%m-%dT%H:%M:%SZ") + "\n";
}

inline void write_provenance(std::FILE* out, int argc, char** argv) {
    std::fputs(provenance_lines(argc, argv).c_str(), out);
}

}  // namespace cdbench
