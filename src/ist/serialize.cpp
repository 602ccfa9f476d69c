// Binary save/load of inner sphere trees (format in include/cdkit/ist/serialize.hpp).
#include "cdkit/ist/serialize.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>

namespace cdkit {
namespace {

constexpr char kMagic[8] = {'C', 'D', 'K', 'I', 'T', 'I', 'S', 'T'};
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kHeader = 8 + 4 + 4 + 8 + 8;

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

// Native-order writes; the byte-order tag lets a reader on another architecture refuse the file.
struct Writer {
    std::vector<std::uint8_t> bytes;
    template <class T> void put(const T& v) {
        // resize + memcpy rather than insert(p, p + sizeof(T)): GCC 12 misreads the latter as an overflow.
        const std::size_t at = bytes.size();
        bytes.resize(at + sizeof(T));
        std::memcpy(bytes.data() + at, &v, sizeof(T));
    }
};

struct Reader {
    const std::vector<std::uint8_t>& bytes;
    std::size_t pos;
    const std::string& source;
    template <class T> T get(const char* what) {
        if (bytes.size() - pos < sizeof(T)) throw Error(source, what, "file is truncated");
        T v;
        std::memcpy(&v, bytes.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
};

}  // namespace

std::vector<std::uint8_t> serialize_inner_sphere_tree(const InnerSphereTree& tree) {
    Writer body;
    body.put(std::int32_t(tree.out_degree()));
    body.put(tree.mesh_volume());
    body.put(std::uint64_t(tree.spheres().size()));
    body.put(std::uint64_t(tree.nodes().size()));
    for (const InnerSphere& s : tree.spheres()) {
        body.put(s.center.x()), body.put(s.center.y()), body.put(s.center.z());
        body.put(s.radius);
    }
    for (double w : tree.cell_weights()) body.put(w);
    for (const IstNode& n : tree.nodes()) {
        body.put(n.center.x()), body.put(n.center.y()), body.put(n.center.z());
        body.put(n.radius), body.put(n.volume), body.put(n.first), body.put(n.count);
    }
    Writer out;
    out.bytes.insert(out.bytes.end(), kMagic, kMagic + 8);
    out.put(kInnerSphereTreeFormatVersion);
    out.put(kByteOrder);
    out.put(std::uint64_t(body.bytes.size()));
    out.put(fnv1a(body.bytes.data(), body.bytes.size()));
    out.bytes.insert(out.bytes.end(), body.bytes.begin(), body.bytes.end());
    return std::move(out.bytes);
}

InnerSphereTree deserialize_inner_sphere_tree(const std::vector<std::uint8_t>& bytes, const std::string& source) {
    if (bytes.size() < kHeader) throw Error(source, "header", "too short to be an inner sphere tree file");
    if (std::memcmp(bytes.data(), kMagic, 8) != 0) throw Error(source, "header", "not an inner sphere tree file (bad magic)");
    Reader r{bytes, 8, source};
    const auto version = r.get<std::uint32_t>("header");
    if (version != kInnerSphereTreeFormatVersion)
        throw Error(source, "header", "format version " + std::to_string(version) + ", this build reads version " +
                                          std::to_string(kInnerSphereTreeFormatVersion));
    if (r.get<std::uint32_t>("header") != kByteOrder) throw Error(source, "header", "written on a machine of other byte order");
    const auto size = r.get<std::uint64_t>("header");
    const auto sum = r.get<std::uint64_t>("header");
    if (size != bytes.size() - kHeader)
        throw Error(source, "header", "payload is " + std::to_string(bytes.size() - kHeader) + " bytes, header says " +
                                          std::to_string(size) + " (truncated or padded file)");
    if (fnv1a(bytes.data() + kHeader, bytes.size() - kHeader) != sum)
        throw Error(source, "checksum", "payload checksum mismatch (corrupt file)");
    const auto degree = r.get<std::int32_t>("payload");
    const auto volume = r.get<double>("payload");
    const auto ns = r.get<std::uint64_t>("payload");
    const auto nn = r.get<std::uint64_t>("payload");
    const std::uint64_t need = ns * 40 + nn * 48;
    if (ns > (1ull << 32) || nn > (1ull << 33) || need != bytes.size() - r.pos)
        throw Error(source, "payload", "sphere and node counts do not match the payload size");
    std::vector<InnerSphere> spheres(ns);
    for (auto& s : spheres) {
        for (int k = 0; k < 3; ++k) s.center[k] = r.get<double>("sphere");
        s.radius = r.get<double>("sphere");
    }
    std::vector<double> weights(ns);
    for (auto& w : weights) w = r.get<double>("weight");
    std::vector<IstNode> nodes(nn);
    for (auto& n : nodes) {
        for (int k = 0; k < 3; ++k) n.center[k] = r.get<double>("node");
        n.radius = r.get<double>("node");
        n.volume = r.get<double>("node");
        n.first = r.get<std::uint32_t>("node");
        n.count = r.get<std::uint32_t>("node");
    }
    return InnerSphereTree::from_parts(std::move(spheres), std::move(weights), std::move(nodes), volume, degree, source);
}

void save_inner_sphere_tree(const InnerSphereTree& tree, const std::string& path) {
    const auto bytes = serialize_inner_sphere_tree(tree);
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw Error(path, "", "cannot open for writing");
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!f) throw Error(path, "", "write failed");
}

InnerSphereTree load_inner_sphere_tree(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error(path, "", "cannot open (missing or unreadable)");
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) throw Error(path, "", "read failed");
    return deserialize_inner_sphere_tree(bytes, path);
}

}  // namespace cdkit
