#pragma once
// Seeded generators of triangle pairs for the triangle tests (test_triangle.cpp, test_triangle_cgal.cpp):
// random pairs and the near-degenerate families where a floating-point test goes wrong. Constructions
// that must be exact (coplanar points, a vertex exactly on a face or an edge, collinear vertices) use
// small integers and dyadic fractions, exact in float as well as in double.
#include "cdkit/core/math.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace cdkit::test::tri {

using V = Vec3<double>;
using Tri = std::array<V, 3>;
struct Pair {
    Tri p, q;
};

/// Bit-exact reproducible random numbers (std::uniform_*_distribution differ between standard libraries).
class Rng {
public:
    explicit Rng(std::uint64_t seed) : g_(seed) {}
    double uniform() { return static_cast<double>(g_() >> 11) * 0x1p-53; }  // [0, 1)
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    int integer(int lo, int hi) { return lo + static_cast<int>(g_() % static_cast<std::uint64_t>(hi - lo + 1)); }
    bool coin(double p = 0.5) { return uniform() < p; }
    V vec(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    V ivec(int lo, int hi) { return {double(integer(lo, hi)), double(integer(lo, hi)), double(integer(lo, hi))}; }
    /// A dyadic number k/16 with k in [lo, hi].
    double dyadic(int lo, int hi) { return integer(lo, hi) / 16.0; }

private:
    std::mt19937_64 g_;
};

enum class Kind {
    random,             // full-precision coordinates, overlapping boxes
    coplanar,           // both triangles exactly in one plane (sometimes an axis plane)
    shared_vertex,      // one common vertex
    shared_edge,        // one common edge, third vertex anywhere (sometimes in the plane)
    vertex_on_face,     // a vertex of Q exactly on P (inside, on an edge, or just outside)
    edge_on_edge,       // an edge of Q passing exactly through a point of an edge of P
    vertex_near_plane,  // a vertex of Q offset from P's plane by 0, ±1 ulp or ±1e-12 … 1e-6
    sliver,             // a nearly collinear triangle
    zero_area,          // collinear or coincident vertices, against any kind of triangle
    huge_offset,        // any of the above moved about 1e6 from the origin
    tiny_scale,         // any of the above scaled by 1e-6
    grid,               // vertices on the 3×3×3 grid {0,1,2}^3: collinear, coplanar, touching all over
    count
};
inline const char* name(Kind k) {
    static const char* n[] = {"random",    "coplanar",          "shared_vertex", "shared_edge", "vertex_on_face",
                              "edge_on_edge", "vertex_near_plane", "sliver",        "zero_area",   "huge_offset",
                              "tiny_scale", "grid"};
    return n[static_cast<int>(k)];
}

inline V cross(const V& a, const V& b) { return a.cross(b); }

/// Small-integer triangle with nonzero area.
inline Tri int_triangle(Rng& r, int range = 8) {
    for (;;) {
        Tri t = {r.ivec(-range, range), r.ivec(-range, range), r.ivec(-range, range)};
        if (cross(t[1] - t[0], t[2] - t[0]).squaredNorm() > 0) return t;
    }
}
/// a + s(b−a) + t(c−a), exact for small integers a, b, c and s, t in sixteenths.
inline V in_plane(const Tri& t, double s, double u) { return t[0] + s * (t[1] - t[0]) + u * (t[2] - t[0]); }

/// A triangle of points of t's plane (exact): barycentric-ish sixteenths, spread around t.
inline Tri plane_triangle(Rng& r, const Tri& t) {
    return {in_plane(t, r.dyadic(-16, 32), r.dyadic(-16, 32)), in_plane(t, r.dyadic(-16, 32), r.dyadic(-16, 32)),
            in_plane(t, r.dyadic(-16, 32), r.dyadic(-16, 32))};
}

inline V near(Rng& r, const V& c, double spread) { return c + r.vec(-spread, spread); }

inline Pair generate(Kind kind, Rng& r);

inline Pair gen_random(Rng& r) {
    Pair x;
    for (auto& v : x.p) v = r.vec(-1, 1);
    const V c = r.vec(-0.6, 0.6);
    for (auto& v : x.q) v = near(r, c, 1.0);
    return x;
}

inline Pair gen_coplanar(Rng& r) {
    Tri base = int_triangle(r);
    if (r.coin(0.25)) {  // an axis-aligned plane, or one parallel to an axis: degenerate projections
        const int k = r.integer(0, 2);
        for (auto& v : base) v[k] = base[0][k];
        if (cross(base[1] - base[0], base[2] - base[0]).squaredNorm() == 0) base = int_triangle(r);
    }
    Pair x{plane_triangle(r, base), plane_triangle(r, base)};
    if (r.coin(0.3)) x.p = base;
    return x;
}

inline Pair gen_shared_vertex(Rng& r) {
    Pair x = gen_random(r);
    x.q[r.integer(0, 2)] = x.p[r.integer(0, 2)];
    return x;
}

inline Pair gen_shared_edge(Rng& r) {
    Pair x;
    x.p = int_triangle(r);
    const int i = r.integer(0, 2), j = (i + 1) % 3;
    V third = r.ivec(-8, 8);
    const int mode = r.integer(0, 2);
    if (mode == 0) third = in_plane(x.p, r.dyadic(-16, 32), r.dyadic(-16, 32));  // coplanar: folds over or not
    else if (mode == 1) third = r.vec(-8, 8);
    x.q = {x.p[j], x.p[i], third};
    return x;
}

inline Pair gen_vertex_on_face(Rng& r) {
    Pair x;
    x.p = int_triangle(r);
    // s, t with s + t in [0, 1] is inside/on the boundary; allow a step outside.
    const double s = r.dyadic(-1, 17), t = r.dyadic(-1, 17 - int(s * 16));
    const V n = cross(x.p[1] - x.p[0], x.p[2] - x.p[0]);
    const V q0 = in_plane(x.p, s, t);
    const double side = r.coin() ? 1.0 : -1.0;
    x.q = {q0, q0 + side * n + r.ivec(-3, 3), q0 + side * n + r.ivec(-3, 3)};
    if (r.coin(0.2)) x.q[1] = q0 - side * n;  // crosses instead of touching
    return x;
}

inline Pair gen_edge_on_edge(Rng& r) {
    Pair x;
    x.p = int_triangle(r);
    const int i = r.integer(0, 2);
    const V X = x.p[i] + r.dyadic(-2, 18) * (x.p[(i + 1) % 3] - x.p[i]);
    const V w = r.ivec(-4, 4);
    const V q0 = X + w, q1 = X - r.dyadic(4, 32) * w;
    const V n = cross(x.p[1] - x.p[0], x.p[2] - x.p[0]);
    const int mode = r.integer(0, 2);
    V q2;
    if (mode == 0) q2 = X + (r.coin() ? 1.0 : -1.0) * n + r.ivec(-2, 2);
    else if (mode == 1) q2 = in_plane(x.p, r.dyadic(-16, 32), r.dyadic(-16, 32));
    else q2 = r.vec(-8, 8);
    x.q = {q0, q1, q2};
    return x;
}

inline Pair gen_vertex_near_plane(Rng& r) {
    Pair x;
    const bool full = r.coin();  // full-precision triangle, or integers
    if (full) {
        for (auto& v : x.p) v = r.vec(-1, 1);
    } else {
        x.p = int_triangle(r);
    }
    const V n = cross(x.p[1] - x.p[0], x.p[2] - x.p[0]);
    const V nn = n.normalized();
    V q0 = in_plane(x.p, r.dyadic(0, 8), r.dyadic(0, 8));  // rounded when `full`: near, not on, the plane
    const int mode = r.integer(0, 6);
    const double sgn = r.coin() ? 1.0 : -1.0;
    if (mode == 1 || mode == 2) {  // ±1 ulp in one coordinate
        const int k = r.integer(0, 2);
        q0[k] = std::nextafter(q0[k], sgn * std::numeric_limits<double>::infinity());
    } else if (mode >= 3) {
        static const double offs[] = {1e-12, 1e-10, 1e-8, 1e-6};
        q0 += sgn * offs[mode - 3] * nn;
    }
    const double side = r.coin() ? 1.0 : -1.0;
    const double scale = full ? 1.0 : 8.0;
    x.q = {q0, q0 + side * scale * nn + r.vec(-scale, scale) * 0.5, q0 + side * scale * nn + r.vec(-scale, scale) * 0.5};
    if (r.coin(0.2)) std::swap(x.p, x.q);
    return x;
}

inline Pair gen_sliver(Rng& r) {
    Pair x;
    const V a = r.vec(-1, 1), b = r.vec(-1, 1);
    V perp = cross(b - a, r.vec(-1, 1));
    if (perp.squaredNorm() > 0) perp.normalize();
    static const double eps[] = {0.0, 1e-16, 1e-14, 1e-11, 1e-8};
    x.p = {a, b, a + r.uniform(-0.5, 1.5) * (b - a) + eps[r.integer(0, 4)] * perp};
    // Q around a point of the line ab, so that it often cuts the sliver.
    const V c = a + r.uniform(0, 1) * (b - a);
    for (auto& v : x.q) v = near(r, c, 1.0);
    if (r.coin(0.3)) std::swap(x.p, x.q);
    return x;
}

inline Tri degenerate_triangle(Rng& r, const V& o, const V& d) {
    // Points on the line o + s·d (exact for integer o, d and sixteenths), sometimes coincident.
    const int mode = r.integer(0, 3);
    if (mode == 0) return {o, o, o};
    if (mode == 1) return {o, o + d, o};
    return {o + r.dyadic(-16, 16) * d, o + r.dyadic(-16, 16) * d, o + r.dyadic(-16, 16) * d};
}

inline Pair gen_zero_area(Rng& r) {
    Pair x;
    const int other = r.integer(0, 3);
    x.q = int_triangle(r);
    if (other == 0) {  // a degenerate triangle lying in Q's plane
        const V o = in_plane(x.q, r.dyadic(-8, 24), r.dyadic(-8, 24));
        const V d = in_plane(x.q, r.dyadic(-8, 24), r.dyadic(-8, 24)) - o;
        x.p = degenerate_triangle(r, o, d);
    } else if (other == 1) {  // through or near Q's interior, crossing the plane
        const V o = in_plane(x.q, r.dyadic(-4, 20), r.dyadic(-4, 20));
        const V d = r.ivec(-4, 4);
        x.p = degenerate_triangle(r, o, d);
    } else if (other == 2) {  // both degenerate, sharing a plane often
        const V o = r.ivec(-4, 4), d = r.ivec(-4, 4);
        x.p = degenerate_triangle(r, o, d);
        const V o2 = r.coin() ? x.p[r.integer(0, 2)] + r.dyadic(-16, 16) * d : r.ivec(-4, 4);
        const V d2 = r.coin() ? d : r.ivec(-4, 4);
        x.q = degenerate_triangle(r, o2, d2);
        if (r.coin(0.3)) x.q = {o2, o2 + d2, o2 + r.dyadic(-8, 8) * (x.p[1] - o2)};
    } else {  // full-precision collinear-ish points vs a random triangle
        const Pair rp = gen_random(r);
        x.q = rp.q;
        const V o = rp.p[0], d = rp.p[1] - rp.p[0];
        x.p = {o, o + 0.5 * d, o + d};  // rounded: collinear only sometimes
    }
    if (r.coin()) std::swap(x.p, x.q);
    return x;
}

inline Pair generate(Kind kind, Rng& r) {
    switch (kind) {
    case Kind::random: return gen_random(r);
    case Kind::coplanar: return gen_coplanar(r);
    case Kind::shared_vertex: return gen_shared_vertex(r);
    case Kind::shared_edge: return gen_shared_edge(r);
    case Kind::vertex_on_face: return gen_vertex_on_face(r);
    case Kind::edge_on_edge: return gen_edge_on_edge(r);
    case Kind::vertex_near_plane: return gen_vertex_near_plane(r);
    case Kind::sliver: return gen_sliver(r);
    case Kind::zero_area: return gen_zero_area(r);
    case Kind::huge_offset:
    case Kind::tiny_scale: {
        Pair x = generate(static_cast<Kind>(r.integer(0, static_cast<int>(Kind::zero_area))), r);
        if (kind == Kind::huge_offset) {
            const V o = r.vec(-1, 1).normalized() * 1e6;
            for (auto* t : {&x.p, &x.q})
                for (auto& v : *t) v += o;
        } else {
            for (auto* t : {&x.p, &x.q})
                for (auto& v : *t) v *= 1e-6;
        }
        return x;
    }
    case Kind::grid: {
        Pair x;
        for (auto* t : {&x.p, &x.q})
            for (auto& v : *t) v = r.ivec(0, 2);
        return x;
    }
    default: return gen_random(r);
    }
}

/// The pair rounded to S (a no-op for double); the oracle must see these rounded values.
template <class S> struct PairS {
    std::array<Vec3<S>, 3> p, q;
};
// Out of line on purpose: GCC 12.2 at -O3 -march=native (AVX-512) was seen to fold the inlined
// double→float→double round trip of 16 of these coordinates into the identity, so that the "float"
// triangles reached the code under test unrounded (and differently rounded than the oracle saw them).
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_TEST_NOINLINE __attribute__((noinline))
#else
#define CDKIT_TEST_NOINLINE
#endif
template <class S> CDKIT_TEST_NOINLINE PairS<S> as(const Pair& x) {
    PairS<S> y;
    for (int i = 0; i < 3; ++i) {
        y.p[i] = x.p[i].cast<S>();
        y.q[i] = x.q[i].cast<S>();
    }
    return y;
}

/// The 6 orderings of a triangle's vertices.
inline constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

}  // namespace cdkit::test::tri
