// Convex pairs saved from the hard-case count (tests/data/convex/*.txt): two shapes and their poses as hexadecimal
// doubles, exact in every build. Lines starting with '#' are comments. A shape is a keyword and its numbers:
// `box hx hy hz`, `capsule radius half_length`, `cone radius half_height`, `ellipsoid rx ry rz`, or `hull n` and n
// points; a pose is three rotation rows and the translation. A malformed file throws, naming the file.
#pragma once

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

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
                          : s.kind == "capsule" || s.kind == "cone" ? 2
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
    } else {
        static_assert(std::is_same_v<Shape<S>, ConvexPolyhedron<S>>);
        expect("hull");
        std::vector<Vec3<S>> points;
        for (std::size_t i = 0; i + 2 < x.size(); i += 3) points.emplace_back(S(x[i]), S(x[i + 1]), S(x[i + 2]));
        return ConvexPolyhedron<S>(points);
    }
}

template <class S> Transform<S> cast_pose(const Transform<double>& p) {
    return Transform<S>(p.R.cast<S>(), p.t.cast<S>());
}

}  // namespace cdkit::test
