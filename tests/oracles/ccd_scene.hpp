#pragma once
// A step of the "Scalable CCD" data (Belgrod et al. 2023) in ../shared/ccd-data/scalable-ccd/<scene>: the mesh at
// the step's start and end (binary PLY, vertex order kept: the data numbers features by it), and the data's
// ground truth: its candidate pairs (boxes/<step>{vf,ee}.json, feature ids numbered vertices, then edges in
// libigl's order, then faces) with the exact answer for each (mma_bool/).

#include <cdkit/core/math.hpp>
#include <cdkit/core/mesh.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cdkit::test {

struct PlyFrame {
    std::vector<cdkit::Vec3<double>> vertices;
    std::vector<cdkit::Triangle> triangles;
};

/// Binary PLY (either byte order) with float or double x, y, z (other vertex properties of 1 byte are skipped)
/// and triangles as `list uchar int`. Throws std::runtime_error naming the file on anything else.
inline PlyFrame read_binary_ply(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::string line, format;
    std::size_t nv = 0, nf = 0;
    std::vector<std::string> vprops;
    std::string element;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ss(line);
        std::string word;
        ss >> word;
        if (word == "format") ss >> format;
        else if (word == "element") {
            std::size_t n = 0;
            ss >> element >> n;
            (element == "vertex" ? nv : nf) = n;
        } else if (word == "property" && element == "vertex") {
            std::string type, name;
            ss >> type >> name;
            vprops.push_back(type);
        } else if (word == "end_header") break;
    }
    const bool big = format == "binary_big_endian";
    if (!big && format != "binary_little_endian") throw std::runtime_error(path + ": not a binary PLY");
    std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t at = 0;
    auto take = [&](std::size_t n) {
        if (at + n > data.size()) throw std::runtime_error(path + ": truncated");
        char buf[8];
        for (std::size_t i = 0; i < n; ++i) buf[i] = data[at + (big ? n - 1 - i : i)];
        at += n;
        return std::string(buf, n);
    };
    PlyFrame f;
    f.vertices.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
        for (std::size_t p = 0; p < vprops.size(); ++p) {
            const std::string& t = vprops[p];
            if (t == "float") {
                float x;
                std::memcpy(&x, take(4).data(), 4);
                if (p < 3) f.vertices[i][int(p)] = x;
            } else if (t == "double") {
                double x;
                std::memcpy(&x, take(8).data(), 8);
                if (p < 3) f.vertices[i][int(p)] = x;
            } else if (t == "uchar" && p >= 3) {
                (void)take(1);
            } else {
                throw std::runtime_error(path + ": unsupported vertex property type " + t);
            }
        }
    f.triangles.resize(nf);
    for (std::size_t i = 0; i < nf; ++i) {
        if (static_cast<unsigned char>(take(1)[0]) != 3) throw std::runtime_error(path + ": a face is not a triangle");
        for (int k = 0; k < 3; ++k) {
            std::int32_t v;
            std::memcpy(&v, take(4).data(), 4);
            if (v < 0 || std::size_t(v) >= nv) throw std::runtime_error(path + ": index out of range");
            f.triangles[i][k] = cdkit::Index(v);
        }
    }
    return f;
}

/// The integers of a JSON file, in order ([[a, b], ...] → a, b, ...).
inline std::vector<long long> read_json_integers(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::vector<long long> out;
    std::string digits;
    char ch;
    while (in.get(ch)) {
        if (ch >= '0' && ch <= '9') digits.push_back(ch);
        else if (!digits.empty()) out.push_back(std::stoll(digits)), digits.clear();
    }
    if (!digits.empty()) out.push_back(std::stoll(digits));
    return out;
}

/// The simulation sets' truth: a JSON array of true/false.
inline std::vector<bool> read_bool_array(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the ground-truth file");
    std::vector<bool> out;
    std::string word;
    char ch;
    while (in.get(ch)) {
        if (std::isalpha(static_cast<unsigned char>(ch))) {
            word.push_back(ch);
            continue;
        }
        if (word == "true") out.push_back(true);
        else if (word == "false") out.push_back(false);
        else if (!word.empty()) throw std::runtime_error(path + ": unexpected word '" + word + "'");
        word.clear();
    }
    return out;
}

}  // namespace cdkit::test

namespace cdkit::test {

/// One step of a scene with the data's candidate pairs and their exact answers, in cdkit's numbering: vertex–face
/// pairs as (vertex, triangle), edge–edge pairs as (edge, edge) with edges indexed as cdkit::mesh_edges() does.
struct CcdSceneStep {
    std::string name;
    PlyFrame start, end;
    struct Pair {
        cdkit::Index a, b;
        bool truth;
    };
    std::vector<Pair> vertex_face, edge_edge;
};

/// `dir` is the scene's folder, `step` the step number, `start_file` and `end_file` the frames' names, `edges`
/// the mesh's edge count (the data numbers faces after the edges).
inline CcdSceneStep read_ccd_scene_step(const std::string& dir, const std::string& step, const std::string& start_file,
                                        const std::string& end_file, std::size_t edges) {
    CcdSceneStep s;
    s.name = dir.substr(dir.find_last_of('/') + 1);
    s.start = read_binary_ply(dir + "/frames/" + start_file);
    s.end = read_binary_ply(dir + "/frames/" + end_file);
    const std::size_t nv = s.start.vertices.size();
    for (const char* kind : {"vf", "ee"}) {
        const auto ids = read_json_integers(dir + "/boxes/" + step + kind + ".json");
        const auto truth = read_bool_array(dir + "/mma_bool/" + step + kind + "_mma_bool.json");
        if (ids.size() != 2 * truth.size()) throw std::runtime_error(dir + ": boxes and answers of " + kind + " differ in count");
        auto& out = std::string(kind) == "vf" ? s.vertex_face : s.edge_edge;
        for (std::size_t i = 0; i < truth.size(); ++i) {
            long long a = ids[2 * i], b = ids[2 * i + 1];
            if (std::string(kind) == "vf") b -= static_cast<long long>(nv + edges);
            else a -= static_cast<long long>(nv), b -= static_cast<long long>(nv);
            if (a < 0 || b < 0) throw std::runtime_error(dir + ": a feature id does not fit the mesh");
            out.push_back({cdkit::Index(a), cdkit::Index(b), truth[i]});
        }
    }
    return s;
}

}  // namespace cdkit::test
