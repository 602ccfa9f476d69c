// Mesh import through assimp. Everything assimp does happens inside import_scene(), which turns every
// failure (error string, exception, bad scene data) into cdkit::Error naming the source.
#include "cdkit/io/load_mesh.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace cdkit {
namespace {

namespace fs = std::filesystem;

/// True when `path` names a regular file (after following symlinks). Never throws.
bool is_regular(const char* path) noexcept {
    std::error_code ec;
    return path && fs::is_regular_file(fs::path(path), ec) && !ec;
}

/// assimp's default file system, except that it opens regular files only, read-only. Importers open side
/// files by names taken from the data (OBJ mtllib, glTF buffers, COLLADA images, X3D inlines); a name
/// that points at a directory, FIFO or device could make them block or misbehave.
class RegularFilesOnly final : public Assimp::DefaultIOSystem {
public:
    bool Exists(const char* file) const override { return is_regular(file); }
    Assimp::IOStream* Open(const char* file, const char* mode = "rb") override {
        if (!mode || std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+')) return nullptr;
        if (!is_regular(file)) return nullptr;
        return Assimp::DefaultIOSystem::Open(file, mode);
    }
};

/// For imports from memory: no file exists, so a side-file name in the bytes cannot reach the disk.
class NoFiles final : public Assimp::DefaultIOSystem {
public:
    bool Exists(const char*) const override { return false; }
    Assimp::IOStream* Open(const char*, const char* = "rb") override { return nullptr; }
};

// ---- pre-checks -------------------------------------------------------------------------------
// assimp trusts the counts in some headers: it allocates what a PLY or OFF header declares before reading
// the body (a 269-byte PLY declaring 2e9 vertices made it touch 23 GB), its OFF reader clamps an
// out-of-range index to the last vertex and drops faces of more than 9 corners with only a log message,
// and a truncated binary STL gets an unhelpful message. These checks read the bytes first and reject such
// files with a precise reason. They mirror how assimp 5.2 reads these formats, and only ever reject.

enum class Precheck { none, ply, off, stl, collada };

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool is_space(char c) noexcept { return c == ' ' || c == '\t' || c == '\v'; }
bool is_line_end(char c) noexcept { return c == '\n' || c == '\r' || c == '\f'; }

bool starts_with_ply(std::string_view d) noexcept {
    return d.size() >= 4 && d.substr(0, 3) == "ply" && (d[3] == '\n' || d[3] == '\r');
}
bool starts_with_off(std::string_view d) noexcept {
    std::size_t i = 0;
    while (i < d.size() && (is_space(d[i]) || is_line_end(d[i]))) ++i;
    d.remove_prefix(i);
    for (std::string_view p : {"ST", "C", "N", "4", "n"})
        if (d.substr(0, p.size()) == p) d.remove_prefix(p.size());
    return d.substr(0, 3) == "OFF";
}

/// Which check applies: by extension, else by content (assimp sniffs the content when no reader takes the
/// extension, and also when the extension's reader declines the bytes).
Precheck precheck_kind(const std::string& ext, std::string_view head) {
    if (ext == "ply") return Precheck::ply;
    if (ext == "off") return Precheck::off;
    if (ext == "stl") return Precheck::stl;
    // assimp falls back to sniffing the content when the extension's reader declines, so a COLLADA document
    // is checked whatever the name says.
    // The same holds for PLY and OFF content under another known extension (a PLY body named .gltf made
    // assimp's PLY reader spin: fuzz/regressions/fuzz_load_mesh-assimp-ply-as-gltf-hang.bin).
    if (ext == "dae" || head.find("<COLLADA") != std::string_view::npos) return Precheck::collada;
    if (starts_with_ply(head)) return Precheck::ply;
    if (starts_with_off(head)) return Precheck::off;
    return Precheck::none;
}

/// Splits text into whitespace-separated tokens.
std::vector<std::string_view> tokens(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (is_space(line[i]) || is_line_end(line[i]))) ++i;
        const std::size_t b = i;
        while (i < line.size() && !is_space(line[i]) && !is_line_end(line[i])) ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

bool parse_u64(std::string_view t, std::uint64_t& v) {
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && p == t.data() + t.size();
}

/// A count from a header: must fit assimp's 32-bit counts.
std::uint64_t header_count(const std::string& source, std::string_view what, std::string_view token) {
    std::uint64_t v = 0;
    if (!parse_u64(token, v))
        throw Error(source, "header",
                    "count of " + std::string(what) + " is not a valid count: '" + std::string(token) + "'");
    if (v > std::numeric_limits<std::uint32_t>::max())
        throw Error(source, "header",
                    "declares " + std::to_string(v) + " " + std::string(what) + ", more than 32-bit counts allow");
    return v;
}

/// Binary STL: 84-byte header, then exactly 50 bytes per facet. assimp reads a file as ASCII when it starts
/// with "solid", and as binary only when the size matches the facet count exactly.
void precheck_stl(const std::string& source, std::string_view head, std::uint64_t size) {
    std::size_t i = 0;
    while (i < head.size() && (is_space(head[i]) || is_line_end(head[i]))) ++i;
    if (head.substr(i, 5) == "solid") return;  // ASCII: no counts to lie about
    if (size < 84)
        throw Error(source, "", "not an ASCII STL (no 'solid') and too small for a binary STL header (84 bytes)");
    std::uint32_t n = 0;
    std::memcpy(&n, head.data() + 80, 4);  // little-endian on every platform assimp supports
    const std::uint64_t need = 84 + 50 * std::uint64_t(n);
    if (need != size)
        throw Error(source, "",
                    "binary STL header declares " + std::to_string(n) + " triangles (" + std::to_string(need) +
                        " bytes) but the file has " + std::to_string(size) + " bytes (truncated or not an STL)");
    if (n == 0) throw Error(source, "", "file contains no triangles (binary STL with 0 facets)");
}

int ply_type_size(std::string_view t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

/// PLY: the header's element counts must match the body (one line per element in ASCII; the exact byte
/// layout in binary, list lengths included). Malformed headers are left to assimp to report.
void precheck_ply(const std::string& source, std::string_view d) {
    struct Prop {
        int count_size = 0;  // > 0: a list, with a length of this many bytes
        bool count_signed = false;
        int size = 0;  // of a value
    };
    struct Element {
        std::string name;
        std::uint64_t count = 0;
        std::vector<Prop> props;
    };
    std::vector<Element> elements;
    std::string format;
    std::size_t pos = 0;
    bool ended = false;
    bool opaque = false;  // a property this check cannot size: leave the body to assimp
    while (pos < d.size() && !ended) {
        std::size_t eol = d.find('\n', pos);
        if (eol == std::string_view::npos) eol = d.size();
        const auto t = tokens(d.substr(pos, eol - pos));
        pos = eol + 1;
        if (t.empty()) continue;
        if (t[0] == "format" && t.size() >= 2)
            format = std::string(t[1]);
        else if (t[0] == "element" && t.size() >= 3) {
            Element e;
            e.name = std::string(t[1]);
            e.count = header_count(source, "'" + e.name + "' elements", t[2]);
            elements.push_back(std::move(e));
        } else if (t[0] == "property" && !elements.empty()) {
            Prop p;
            if (t.size() >= 5 && t[1] == "list") {
                p.count_size = ply_type_size(t[2]);
                p.count_signed = t[2].front() != 'u';
                p.size = ply_type_size(t[3]);
                if (!p.count_size || !p.size) opaque = true;
            } else if (t.size() >= 3) {
                if (!(p.size = ply_type_size(t[1]))) opaque = true;
            } else {
                opaque = true;
            }
            elements.back().props.push_back(p);
        } else if (t[0] == "end_header") {
            ended = true;
        }
    }
    // assimp 5.2.5's PLY reader never returns on a header without end_header (found by fuzz_load_mesh,
    // fuzz/regressions/fuzz_load_mesh-assimp-ply-hang.bin); every PLY file needs one.
    if (!ended) throw Error(source, "", "PLY header has no 'end_header' line (truncated, or not a PLY file)");
    if (opaque) return;
    const std::string_view body = d.substr(std::min(pos, d.size()));
    const auto ends_early = [&](const Element& e, std::uint64_t k, const std::string& what) {
        return Error(source, e.name + " " + std::to_string(k),
                     "file ends early: the header declares " + std::to_string(e.count) + " '" + e.name +
                         "' elements but " + what + " (the header lies about counts, or the file is truncated)");
    };

    if (format == "ascii") {
        // assimp reads one element per line; blank lines are skipped.
        std::uint64_t lines = 0;
        for (std::size_t i = 0; i < body.size();) {
            std::size_t eol = body.find('\n', i);
            if (eol == std::string_view::npos) eol = body.size();
            if (!tokens(body.substr(i, eol - i)).empty()) ++lines;
            i = eol + 1;
        }
        std::uint64_t before = 0;
        for (const Element& e : elements) {
            if (lines < before + e.count)
                throw ends_early(e, lines - before, "the body holds only " + std::to_string(lines) + " lines in all");
            before += e.count;
        }
        if (lines > before)
            throw Error(source, "",
                        "the body holds " + std::to_string(lines) + " lines but the header declares " +
                            std::to_string(before) + " elements (the header lies about counts)");
        // Every list length that is present must be a positive integer: assimp 5.2.5 aborts
        // (ai_assert in TriangulateProcess) on a face of length 0 or a non-numeric length (found by
        // fuzz_load_mesh, fuzz/regressions/fuzz_load_mesh-assimp-ply-triangulate-abort.bin).
        std::size_t i = 0;
        for (const Element& e : elements) {
            for (std::uint64_t k = 0; k < e.count;) {
                std::size_t eol = body.find('\n', i);
                if (eol == std::string_view::npos) eol = body.size();
                const auto t = tokens(body.substr(i, eol - i));
                i = eol + 1;
                if (t.empty()) continue;
                // Only what makes assimp abort is rejected: a short line is left to assimp (Blender writes
                // an empty vertex list property, assimp's own issue623.ply).
                std::size_t at_token = 0;
                for (const Prop& p : e.props) {
                    if (at_token >= t.size()) break;
                    if (p.count_size == 0) {
                        ++at_token;
                        continue;
                    }
                    std::uint64_t n = 0;
                    const std::string_view c = t[at_token];
                    const auto r = std::from_chars(c.data(), c.data() + c.size(), n);
                    if (r.ec != std::errc() || r.ptr != c.data() + c.size() || n == 0)
                        throw Error(source, e.name + " " + std::to_string(k),
                                    "list length '" + std::string(c) + "' is not a positive integer");
                    at_token += 1 + n;
                }
                ++k;
            }
        }
        return;
    }
    const bool little = format == "binary_little_endian";
    if (!little && format != "binary_big_endian") return;
    std::uint64_t at = 0;  // offset into body
    for (const Element& e : elements) {
        bool has_list = false;
        std::uint64_t fixed = 0;
        for (const Prop& p : e.props) {
            has_list = has_list || p.count_size > 0;
            fixed += p.count_size > 0 ? 0 : std::uint64_t(p.size);
        }
        if (!has_list) {  // fixed-size records: one multiplication, no loop over a possibly huge count
            if (fixed > 0 && e.count > (body.size() - at) / fixed)
                throw ends_early(e, (body.size() - at) / fixed, "the body has bytes for fewer");
            // Records without properties take no bytes, but assimp still allocates one object per record.
            if (fixed == 0 && e.count > body.size())
                throw Error(source, "header",
                            "declares " + std::to_string(e.count) + " '" + e.name + "' elements without properties");
            at += e.count * fixed;
            continue;
        }
        for (std::uint64_t k = 0; k < e.count; ++k) {  // every record takes at least one byte: bounded by the size
            for (const Prop& p : e.props) {
                if (p.count_size == 0) {
                    if (body.size() - at < std::uint64_t(p.size))
                        throw ends_early(e, k, "the body has bytes for fewer");
                    at += p.size;
                    continue;
                }
                if (body.size() - at < std::uint64_t(p.count_size))
                    throw ends_early(e, k, "the body has bytes for fewer");
                unsigned char b[4] = {0, 0, 0, 0};
                for (int i = 0; i < p.count_size; ++i)
                    b[i] = static_cast<unsigned char>(body[at + (little ? i : p.count_size - 1 - i)]);
                at += p.count_size;
                std::uint64_t n =
                    b[0] | (std::uint64_t(b[1]) << 8) | (std::uint64_t(b[2]) << 16) | (std::uint64_t(b[3]) << 24);
                if (p.count_signed && (b[p.count_size - 1] & 0x80))
                    throw Error(source, e.name + " " + std::to_string(k), "negative list length");
                if (n > (body.size() - at) / std::uint64_t(p.size))
                    throw ends_early(e, k, "a list runs past the end of the file");
                at += n * p.size;
            }
        }
    }
}

/// OFF, as assimp reads it: a header (optional [ST][C][N][4][n]OFF keyword, then counts, '#' comments
/// allowed), then one vertex per line and one face per line ("n i0 … i(n-1)"); blank lines are skipped.
void precheck_off(const std::string& source, std::string_view d) {
    if (const std::size_t nul = d.find('\0'); nul != std::string_view::npos)
        d = d.substr(0, nul);  // assimp stops at NUL
    std::size_t p = 0;
    const auto next_token = [&] {  // skip blanks, line ends and comment lines
        for (;;) {
            while (p < d.size() && (is_space(d[p]) || is_line_end(d[p]))) ++p;
            if (p < d.size() && d[p] == '#') {
                while (p < d.size() && d[p] != '\n') ++p;
                continue;
            }
            return;
        }
    };
    // Counts are read as assimp's strtoul10 does: the leading digits of the token, nothing more.
    const auto read_digits = [&] {
        next_token();
        const std::size_t b = p;
        while (p < d.size() && d[p] >= '0' && d[p] <= '9') ++p;
        return d.substr(b, p - b);
    };
    next_token();
    bool homogeneous = false, dimension = false;
    if (d.substr(p, 2) == "ST") p += 2;
    if (d.substr(p, 1) == "C") ++p;
    if (d.substr(p, 1) == "N") ++p;
    if (d.substr(p, 1) == "4") {
        homogeneous = true;
        ++p;
    }
    if (d.substr(p, 1) == "n") {
        dimension = true;
        ++p;
    }
    if (d.substr(p, 3) == "OFF") {
        p += 3;
    } else {
        homogeneous = dimension = false;
    }
    std::uint64_t dims = 3;
    if (dimension && !parse_u64(read_digits(), dims)) return;  // malformed: assimp reports it
    const std::string_view nv_text = read_digits(), nf_text = read_digits();
    if (nv_text.empty() || nf_text.empty()) return;  // assimp reads 0 and reports it
    const std::uint64_t nv = header_count(source, "vertices", nv_text);
    const std::uint64_t nf = header_count(source, "faces", nf_text);
    read_digits();                   // edge count, unused
    if (nv == 0 || nf == 0) return;  // assimp reports these
    next_token();

    std::uint64_t line_no = 0;
    const std::uint64_t coords = std::min<std::uint64_t>(dims, 3) + (homogeneous ? 1 : 0);
    while (line_no < nv + nf) {
        while (p < d.size() && is_line_end(d[p])) ++p;
        if (p >= d.size()) break;
        std::size_t eol = p;
        while (eol < d.size() && !is_line_end(d[eol])) ++eol;
        const std::string_view line = d.substr(p, eol - p);
        p = eol;
        const bool is_vertex = line_no < nv;
        const std::string element =
            is_vertex ? "vertex " + std::to_string(line_no) : "face " + std::to_string(line_no - nv);
        ++line_no;
        if (line.size() >= 4096)
            throw Error(source, element, "line is longer than assimp's OFF reader allows (4095 characters)");
        const auto t = tokens(line);
        if (is_vertex) {
            if (t.size() < coords)
                throw Error(source, element,
                            "expected " + std::to_string(coords) + " coordinates, found " + std::to_string(t.size()));
            continue;
        }
        std::uint64_t n = 0;
        if (t.empty() || !parse_u64(t[0], n))
            throw Error(source, element, "face line does not start with a corner count");
        if (n == 0 || n > 9)
            throw Error(source, element,
                        "face has " + std::to_string(n) + " corners; assimp's OFF reader takes 1 to 9");
        if (t.size() < n + 1)
            throw Error(source, element, "face lists fewer than its " + std::to_string(n) + " vertex indices");
        for (std::uint64_t k = 1; k <= n; ++k) {
            std::uint64_t vi = 0;
            if (!parse_u64(t[k], vi))
                throw Error(source, element, "vertex index is not a number: '" + std::string(t[k]) + "'");
            if (vi >= nv)
                throw Error(
                    source, element,
                    "vertex index " + std::to_string(vi) + " out of range (" + std::to_string(nv) + " vertices)");
        }
    }
    if (line_no < nv + nf)
        throw Error(source, line_no < nv ? "vertex " + std::to_string(line_no) : "face " + std::to_string(line_no - nv),
                    "file ends early: the header declares " + std::to_string(nv) + " vertices and " +
                        std::to_string(nf) + " faces (the header lies about counts, or the file is truncated)");
}

/// The value of attribute `name` in the tag text `tag` ("" when absent).
std::string_view xml_attribute(std::string_view tag, std::string_view name) {
    for (std::size_t at = tag.find(name); at != std::string_view::npos; at = tag.find(name, at + 1)) {
        const std::size_t eq = at + name.size();
        if (at > 0 && !is_space(tag[at - 1]) && !is_line_end(tag[at - 1])) continue;
        if (eq + 1 >= tag.size() || tag[eq] != '=' || (tag[eq + 1] != '"' && tag[eq + 1] != '\'')) continue;
        const std::size_t end = tag.find(tag[eq + 1], eq + 2);
        if (end == std::string_view::npos) return {};
        return tag.substr(eq + 2, end - eq - 2);
    }
    return {};
}

/// COLLADA: every <float_array> holds as many numbers as its count says, and every <accessor> reads no
/// further than its array. assimp 5.2 trusts both and dereferences null on a lying count (found by
/// fuzz_load_mesh; fuzz/regressions/fuzz_load_mesh-assimp-collada-count-segv.bin).
void precheck_collada(const std::string& source, std::string_view d) {
    std::vector<std::pair<std::string_view, std::uint64_t>> arrays;  // (id, values held)
    for (std::size_t at = d.find("<float_array"); at != std::string_view::npos; at = d.find("<float_array", at + 1)) {
        const std::size_t close = d.find('>', at);
        if (close == std::string_view::npos) throw Error(source, "float_array", "unterminated tag");
        const std::string_view tag = d.substr(at, close - at);
        const std::string_view id = xml_attribute(tag, "id");
        std::uint64_t declared = 0;
        if (!parse_u64(xml_attribute(tag, "count"), declared))
            throw Error(source, "float_array " + std::string(id), "missing or unreadable count");
        std::uint64_t held = 0;
        if (tag.empty() || tag.back() != '/') {
            const std::size_t end = d.find("</float_array", close);
            if (end == std::string_view::npos) throw Error(source, "float_array " + std::string(id), "unterminated");
            held = tokens(d.substr(close + 1, end - close - 1)).size();
        }
        if (held != declared)
            throw Error(source, "float_array " + std::string(id),
                        "count says " + std::to_string(declared) + " values, the array holds " + std::to_string(held));
        arrays.emplace_back(id, held);
    }
    for (std::size_t at = d.find("<accessor"); at != std::string_view::npos; at = d.find("<accessor", at + 1)) {
        const std::size_t close = d.find('>', at);
        if (close == std::string_view::npos) throw Error(source, "accessor", "unterminated tag");
        const std::string_view tag = d.substr(at, close - at);
        std::string_view src = xml_attribute(tag, "source");
        if (!src.empty() && src.front() == '#') src.remove_prefix(1);
        std::uint64_t count = 0, stride = 1, offset = 0;
        if (!parse_u64(xml_attribute(tag, "count"), count))
            throw Error(source, "accessor " + std::string(src), "missing or unreadable count");
        if (!xml_attribute(tag, "stride").empty() && !parse_u64(xml_attribute(tag, "stride"), stride))
            throw Error(source, "accessor " + std::string(src), "unreadable stride");
        if (!xml_attribute(tag, "offset").empty() && !parse_u64(xml_attribute(tag, "offset"), offset))
            throw Error(source, "accessor " + std::string(src), "unreadable offset");
        for (const auto& [id, held] : arrays)
            if (id == src && (stride > held || count > held || offset + count * stride > held))
                throw Error(source, "accessor " + std::string(src),
                            "reads " + std::to_string(count) + " × " + std::to_string(stride) + " values from an array of " +
                                std::to_string(held));
    }
}

void precheck(const std::string& source, Precheck kind, std::string_view data, std::uint64_t size) {
    switch (kind) {
        case Precheck::collada: precheck_collada(source, data); break;
        case Precheck::ply: precheck_ply(source, data); break;
        case Precheck::off: precheck_off(source, data); break;
        case Precheck::stl: precheck_stl(source, data, size); break;
        case Precheck::none: break;
    }
}

// ---- import -----------------------------------------------------------------------------------------

unsigned int import_flags(const LoadOptions& options) {
    // ValidateDataStructure makes assimp check its own output (index ranges, counts) before we read it.
    // aiProcess_JoinIdenticalVertices is deliberately not used: it merges vertices within a few ulps (and
    // drops unreferenced ones), which moves geometry — on the 871k-triangle Stanford dragon it merges
    // distinct vertices 6e-8 apart and creates two degenerate triangles. join_identical_vertices() below
    // joins bit-identical positions only.
    // These run in a second step (ApplyPostProcessing), after check_faces() has rejected faces without
    // corners: on those, assimp's post-processing steps assert or crash (fuzz/regressions/).
    unsigned int flags = aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    if (options.triangulate) flags |= aiProcess_Triangulate;
    return flags;
}

/// Rejects faces that assimp's post-processing cannot handle: no corners, or corners out of range.
void check_faces(const aiScene& scene, const std::string& source) {
    for (unsigned int mi = 0; mi < scene.mNumMeshes; ++mi) {
        const aiMesh* m = scene.mMeshes[mi];
        if (!m || !m->mFaces) continue;
        for (unsigned int f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            const std::string where = "mesh " + std::to_string(mi) + " face " + std::to_string(f);
            if (face.mNumIndices == 0 || !face.mIndices) throw Error(source, where, "face has no corners");
            for (unsigned int k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= m->mNumVertices)
                    throw Error(source, where,
                                "vertex index " + std::to_string(face.mIndices[k]) + " out of range (" +
                                    std::to_string(m->mNumVertices) + " vertices)");
        }
    }
}

void configure(Assimp::Importer& importer) {
    // Without this, a file holding only a skeleton becomes a mesh of bone glyphs, which is not geometry.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
    // Points and lines are dropped below (rather than by AI_CONFIG_PP_SBP_REMOVE) so that a file holding
    // only them gets the "no triangles" error instead of an assimp error about an empty scene.
}

using Affine = Eigen::Matrix<double, 3, 4>;

Affine to_affine(const aiMatrix4x4& m) {
    Affine a;
    a << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4;
    return a;
}

Affine compose(const Affine& parent, const Affine& child) {
    Affine r;
    r.leftCols<3>() = parent.leftCols<3>() * child.leftCols<3>();
    r.col(3) = parent.leftCols<3>() * child.col(3) + parent.col(3);
    return r;
}

std::string mesh_label(const aiMesh& m, unsigned int index) {
    std::string s = "mesh " + std::to_string(index);
    if (m.mName.length > 0) s += " '" + std::string(m.mName.C_Str()) + "'";
    return s;
}

bool has_triangles(const aiMesh& m) noexcept {
    return (m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) && m.mNumVertices > 0 && m.mNumFaces > 0;
}

/// Appends one instance of `m`, transformed by `x`, to `out`. Faces that are not triangles are skipped
/// (points and lines always; polygons when triangulation is off).
void append_mesh(const aiMesh& m, unsigned int mesh_index, const Affine& x, TriangleMesh<double>& out) {
    if (!has_triangles(m)) return;
    if (!m.mVertices || !m.mFaces)
        throw Error(out.source, mesh_label(m, mesh_index), "importer returned a mesh without vertex or face data");
    const std::size_t base = out.vertices.size();  // below 2^32 - mNumVertices: checked by collect()
    for (unsigned int i = 0; i < m.mNumVertices; ++i) {
        const aiVector3D& p = m.mVertices[i];
        const Vec3<double> v = x.leftCols<3>() * Vec3<double>(p.x, p.y, p.z) + x.col(3);
        // Checked here, before any joining, so "vertex N" is the position in the imported order; the
        // transform itself can overflow to infinity, which this catches too.
        if (!v.allFinite())
            throw Error(out.source, "vertex " + std::to_string(out.vertices.size()), "coordinate is NaN or infinite");
        out.vertices.push_back(v);
    }
    for (unsigned int f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3) continue;
        if (!face.mIndices)
            throw Error(out.source, mesh_label(m, mesh_index) + " face " + std::to_string(f), "face has no indices");
        Triangle t;
        for (int k = 0; k < 3; ++k) {
            const unsigned int vi = face.mIndices[k];
            if (vi >= m.mNumVertices)
                throw Error(out.source, mesh_label(m, mesh_index) + " face " + std::to_string(f),
                            "vertex index " + std::to_string(vi) + " out of range (" + std::to_string(m.mNumVertices) +
                                " vertices)");
            t[k] = static_cast<Index>(base + vi);
        }
        out.triangles.push_back(t);
    }
}

/// Calls visit(mesh index, world transform) for every mesh reference in the node graph, depth first in
/// file order. Iterative, with depth and node bounds, because the graph comes from untrusted data.
template <class Visit> void walk_nodes(const aiScene& scene, const std::string& source, Visit&& visit) {
    if (!scene.mRootNode) throw Error(source, "", "scene has no root node");
    if (scene.mNumMeshes > 0 && !scene.mMeshes) throw Error(source, "", "scene mesh table is missing");
    constexpr std::size_t max_depth = 1024;
    constexpr std::size_t max_nodes = std::size_t(1) << 24;
    struct Item {
        const aiNode* node;
        Affine parent;
        std::size_t depth;
    };
    Affine identity = Affine::Zero();
    identity.leftCols<3>().setIdentity();
    std::vector<Item> stack{{scene.mRootNode, identity, 0}};
    std::size_t visited = 0;
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        if (++visited > max_nodes) throw Error(source, "", "node graph is too large or cyclic");
        if (it.depth > max_depth) throw Error(source, "", "node graph is too deep or cyclic");
        const aiNode& node = *it.node;
        const Affine x = compose(it.parent, to_affine(node.mTransformation));
        if (node.mNumMeshes > 0 && !node.mMeshes)
            throw Error(source, "node '" + std::string(node.mName.C_Str()) + "'", "mesh list is missing");
        for (unsigned int i = 0; i < node.mNumMeshes; ++i) {
            const unsigned int mi = node.mMeshes[i];
            if (mi >= scene.mNumMeshes || !scene.mMeshes[mi])
                throw Error(source, "node '" + std::string(node.mName.C_Str()) + "'",
                            "mesh index " + std::to_string(mi) + " out of range");
            visit(mi, x);
        }
        // Children pushed in reverse so that the output follows the file's node order.
        for (unsigned int c = node.mNumChildren; c-- > 0;)
            if (node.mChildren && node.mChildren[c]) stack.push_back({node.mChildren[c], x, it.depth + 1});
    }
}

/// Every mesh instance of the scene, transformed, into `out`. A first pass adds up the instanced sizes, so
/// that a scene too large for 32-bit indices (a small file can instance a big mesh many times) is
/// rejected before anything is allocated, and the second pass allocates exactly once.
void collect(const aiScene& scene, TriangleMesh<double>& out) {
    constexpr std::uint64_t not_counted = ~std::uint64_t(0);
    std::vector<std::uint64_t> triangles_of(scene.mNumMeshes, not_counted);  // per mesh, counted once
    std::uint64_t vertices = 0, triangles = 0;
    walk_nodes(scene, out.source, [&](unsigned int mi, const Affine&) {
        const aiMesh& m = *scene.mMeshes[mi];
        if (!has_triangles(m)) return;
        if (triangles_of[mi] == not_counted) {
            triangles_of[mi] = 0;
            if (m.mFaces)
                for (unsigned int f = 0; f < m.mNumFaces; ++f) triangles_of[mi] += m.mFaces[f].mNumIndices == 3;
        }
        vertices += m.mNumVertices;
        triangles += triangles_of[mi];
        constexpr std::uint64_t max_index = std::numeric_limits<Index>::max();
        if (vertices > max_index || triangles > max_index)
            throw Error(out.source, "",
                        "scene (instances included) has more vertices or triangles than 32-bit indices can address");
    });
    out.vertices.reserve(static_cast<std::size_t>(vertices));
    out.triangles.reserve(static_cast<std::size_t>(triangles));
    walk_nodes(scene, out.source,
               [&](unsigned int mi, const Affine& x) { append_mesh(*scene.mMeshes[mi], mi, x, out); });
}

/// Runs `read` (which calls the importer), converts the scene and finishes the mesh. Every exception that
/// is not already a cdkit::Error becomes one naming `source`.
template <class Read>
TriangleMesh<double> import_scene(const std::string& source, const LoadOptions& options, Read&& read) {
    TriangleMesh<double> mesh;
    mesh.source = source;
    try {
        Assimp::Importer importer;
        configure(importer);
        const aiScene* scene = read(importer, 0u);
        if (!scene) {
            std::string why = importer.GetErrorString();
            if (why.empty()) why = "assimp could not read it (unknown or unsupported format)";
            throw Error(source, "", "import failed: " + why);
        }
        check_faces(*scene, source);
        scene = importer.ApplyPostProcessing(import_flags(options));
        if (!scene) throw Error(source, "", std::string("import failed: ") + importer.GetErrorString());
        collect(*scene, mesh);
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(source, "", "out of memory while importing (sizes in the file are too large?)");
    } catch (const std::exception& e) {
        throw Error(source, "", std::string("import failed: ") + e.what());
    } catch (...) {
        throw Error(source, "", "import failed: unknown exception from assimp");
    }
    if (mesh.triangles.empty()) throw Error(source, "", "file contains no triangles");
    if (options.join_vertices) join_identical_vertices(mesh);
    validate(mesh);
    return mesh;
}

}  // namespace

TriangleMesh<double> load_mesh(const std::string& path, const LoadOptions& options) {
    if (path.empty()) throw Error("<input>", "", "empty file path");
    std::error_code ec;
    const fs::path fpath(path);
    const fs::file_status st = fs::status(fpath, ec);
    if (ec && ec != std::errc::no_such_file_or_directory) throw Error(path, "", "cannot access file: " + ec.message());
    if (!fs::exists(st)) throw Error(path, "", "file not found");
    if (fs::is_directory(st)) throw Error(path, "", "not a regular file (it is a directory)");
    if (!fs::is_regular_file(st)) throw Error(path, "", "not a regular file (device, FIFO or socket)");
    const std::uintmax_t size = fs::file_size(fpath, ec);
    if (ec) throw Error(path, "", "cannot access file: " + ec.message());
    if (size == 0) throw Error(path, "", "file is empty");

    std::ifstream in(fpath, std::ios::binary);
    if (!in) {
        const int err = errno;
        throw Error(path, "",
                    std::string("cannot open file for reading") + (err ? ": " + std::string(std::strerror(err)) : ""));
    }
    std::string head(static_cast<std::size_t>(std::min<std::uintmax_t>(size, 512)), '\0');
    if (!in.read(head.data(), static_cast<std::streamsize>(head.size()))) throw Error(path, "", "cannot read file");

    return import_scene(path, options, [&](Assimp::Importer& importer, unsigned int flags) {
        const std::string ext = lower(fpath.extension().string());  // ".ply" or ""
        const Precheck kind = precheck_kind(ext.empty() ? ext : ext.substr(1), head);
        if (kind == Precheck::stl || kind == Precheck::none) {
            precheck(path, kind, head, size);
        } else {  // PLY, OFF and COLLADA checks read the whole file (a fraction of what assimp then spends on it)
            std::string all(static_cast<std::size_t>(size), '\0');
            in.seekg(0);
            if (!in.read(all.data(), static_cast<std::streamsize>(all.size())))
                throw Error(path, "", "cannot read file");
            precheck(path, kind, all, size);
        }
        in.close();
        importer.SetIOHandler(new RegularFilesOnly);  // the importer owns and deletes it
        return importer.ReadFile(path, flags);
    });
}

TriangleMesh<double> load_mesh_from_memory(const void* data, std::size_t size, const std::string& format_hint,
                                           const LoadOptions& options, const std::string& name) {
    const std::string source = name.empty() ? std::string("<memory>") : name;
    if (size == 0) throw Error(source, "", "input is empty");
    if (!data) throw Error(source, "", "null data pointer");
    // assimp wants the bare extension ("obj", not ".obj") and rejects hints longer than its limit.
    std::string hint = lower(format_hint);
    while (!hint.empty() && hint.front() == '.') hint.erase(hint.begin());
    if (hint.size() > Assimp::Importer::MaxLenHint) throw Error(source, "", "format hint is too long");

    return import_scene(source, options, [&](Assimp::Importer& importer, unsigned int flags) {
        const std::string_view bytes(static_cast<const char*>(data), size);
        precheck(source, precheck_kind(hint, bytes.substr(0, 512)), bytes, size);
        importer.SetIOHandler(new NoFiles);
        return importer.ReadFileFromMemory(data, size, flags, hint.c_str());
    });
}

}  // namespace cdkit
