// Convex pairs saved from the hard-case count (tests/data/convex/*.txt): two shapes and their poses as hexadecimal
// doubles, exact in every build. Lines starting with '#' are comments. A shape is a keyword and its numbers:
// `box hx hy hz`, `capsule radius half_length`, `cone radius half_height`, `cylinder radius half_height`,
// `sphere radius`, `ellipsoid rx ry rz`, or `hull n` and n points; a pose is three rotation rows and the translation. A malformed
// file throws, naming the file. `write_convex_case` writes one (to save a pair the count found).
#pragma once

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cdkit::test {

struct CaseShape {
    std::string kind;
    std::vector<double> numbers;     ///< the primitive's parameters, or the hull's points (x, y, z each)
};

struct ConvexCase {
    CaseShape a, b;
    Transform<double> pose_a, pose_b;
};

inline ConvexCase read_convex_case(const std::string& path) {
    std::ifstream file(path);
    if (!file) throw std::runtime_error(path + ": cannot open");
    std::stringstream text;  // without the comment lines
    for (std::string line; std::getline(file, line);)
        if (line.empty() || line[0] != '#') text << line << '\n';
    auto number = [&] {
        std::string token;
        if (!(text >> token)) throw std::runtime_error(path + ": ends early");
        std::size_t used = 0;
        const double v = std::stod(token, &used);  // strtod reads hexadecimal floating literals
        if (used != token.size()) throw std::runtime_error(path + ": not a number: " + token);
        return v;
    };
    auto shape = [&] {
        CaseShape s;
        if (!(text >> s.kind)) throw std::runtime_error(path + ": ends early");
        const int count = s.kind == "box" || s.kind == "ellipsoid" ? 3
                          : s.kind == "capsule" || s.kind == "cone" || s.kind == "cylinder" ? 2
                          : s.kind == "sphere"                        ? 1
                          : s.kind == "hull"                          ? -1
                                                                      : 0;
        if (count == 0) throw std::runtime_error(path + ": unknown shape " + s.kind);
        const int n = count > 0 ? count : 3 * int(number());
        for (int i = 0; i < n; ++i) s.numbers.push_back(number());
        return s;
    };
    auto pose = [&] {
        Mat3<double> r;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) r(i, j) = number();
        Vec3<double> t;
        for (int k = 0; k < 3; ++k) t[k] = number();
        return Transform<double>(r, t);
    };
    ConvexCase c;
    c.a = shape();
    c.b = shape();
    c.pose_a = pose();
    c.pose_b = pose();
    return c;
}

/// The saved shape as Shape<S> (the caller names the class the file holds; a mismatch throws).
template <template <class> class Shape, class S> Shape<S> build(const CaseShape& c) {
    const auto& x = c.numbers;
    auto expect = [&](const char* kind) {
        if (c.kind != kind) throw std::runtime_error("convex case: expected " + std::string(kind) + ", got " + c.kind);
    };
    if constexpr (std::is_same_v<Shape<S>, Box<S>>) {
        expect("box");
        return Box<S>(Vec3<S>(S(x[0]), S(x[1]), S(x[2])));
    } else if constexpr (std::is_same_v<Shape<S>, Ellipsoid<S>>) {
        expect("ellipsoid");
        return Ellipsoid<S>(Vec3<S>(S(x[0]), S(x[1]), S(x[2])));
    } else if constexpr (std::is_same_v<Shape<S>, Capsule<S>>) {
        expect("capsule");
        return Capsule<S>(S(x[0]), S(x[1]));
    } else if constexpr (std::is_same_v<Shape<S>, Cone<S>>) {
        expect("cone");
        return Cone<S>(S(x[0]), S(x[1]));
    } else if constexpr (std::is_same_v<Shape<S>, Sphere<S>>) {
        expect("sphere");
        return Sphere<S>(S(x[0]));
    } else if constexpr (std::is_same_v<Shape<S>, Cylinder<S>>) {
        expect("cylinder");
        return Cylinder<S>(S(x[0]), S(x[1]));
    } else {
        static_assert(std::is_same_v<Shape<S>, ConvexPolyhedron<S>>);
        expect("hull");
        std::vector<Vec3<S>> points;
        for (std::size_t i = 0; i + 2 < x.size(); i += 3) points.emplace_back(S(x[i]), S(x[i + 1]), S(x[i + 2]));
        return ConvexPolyhedron<S>(points);
    }
}

/// The keyword and numbers of a shape, as `read_convex_case` reads them (hexadecimal: exact).
inline std::string hex(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%a", x);
    return buf;
}
inline std::string case_text(const Box<double>& s) { return "box " + hex(s.half[0]) + " " + hex(s.half[1]) + " " + hex(s.half[2]); }
inline std::string case_text(const Ellipsoid<double>& s) {
    return "ellipsoid " + hex(s.radii[0]) + " " + hex(s.radii[1]) + " " + hex(s.radii[2]);
}
inline std::string case_text(const Capsule<double>& s) { return "capsule " + hex(s.radius) + " " + hex(s.half_length); }
inline std::string case_text(const Cone<double>& s) { return "cone " + hex(s.radius) + " " + hex(s.half_height); }
inline std::string case_text(const Sphere<double>& s) { return "sphere " + hex(s.radius); }
inline std::string case_text(const Cylinder<double>& s) { return "cylinder " + hex(s.radius) + " " + hex(s.half_height); }
inline std::string case_text(const ConvexPolyhedron<double>& s) {
    std::string t = "hull " + std::to_string(s.vertices().size());
    for (const auto& p : s.vertices()) t += "\n" + hex(p.x()) + " " + hex(p.y()) + " " + hex(p.z());
    return t;
}
inline std::string case_text(const Transform<double>& p) {
    std::string t;
    for (int i = 0; i < 3; ++i) t += hex(p.R(i, 0)) + " " + hex(p.R(i, 1)) + " " + hex(p.R(i, 2)) + "\n";
    return t + hex(p.t[0]) + " " + hex(p.t[1]) + " " + hex(p.t[2]) + "\n";
}

/// Writes a pair in the format above, `comment` as its second comment line; throws naming the file on failure.
template <class A, class B>
void write_convex_case(const std::string& path, const std::string& comment, const A& a, const Transform<double>& pa,
                       const B& b, const Transform<double>& pb) {
    std::ofstream file(path);
    file << "# cdkit convex case: shape A, shape B, then A's and B's pose (3 rotation rows, translation); "
            "hexadecimal doubles\n# "
         << comment << "\n" << case_text(a) << "\n" << case_text(b) << "\n" << case_text(pa) << case_text(pb);
    if (!file) throw std::runtime_error(path + ": cannot write");
}

template <class S> Transform<S> cast_pose(const Transform<double>& p) {
    return Transform<S>(p.R.cast<S>(), p.t.cast<S>());
}

}  // namespace cdkit::test
