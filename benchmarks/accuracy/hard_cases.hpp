#pragma once
/// \file The hard-case corpus of the accuracy benchmark: seeded, reproducible generators of triangle pairs.
///
/// The twelve base families (random, coplanar, shared vertex/edge, vertex on face, edge on edge, vertex near
/// plane at 0 / ±1 ulp / ±1e-12 … 1e-6, slivers, zero-area, huge offset 1e6, tiny scale 1e-6, the {0,1,2}^3
/// grid) are the test suite's generators (tests/narrowphase/triangle_cases.hpp), reused so that the
/// benchmark measures the same corpus the tests check. This header adds the families the tests lack:
/// near-parallel edges, touching along an edge, duplicated faces, and all 36 vertex orders (× both argument
/// orders) of a hard case. Exactness of constructions follows the tests' rule: whatever must be exact
/// (a point on a line, on a plane) is built from small integers and sixteenths.

#include "narrowphase/triangle_cases.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace cdkit::accuracy {

namespace tri = cdkit::test::tri;
using tri::Pair;
using tri::Rng;
using tri::Tri;
using tri::V;

/// Corpus families: the tests' base kinds first (same numbering as tri::Kind), then the extra ones.
enum class Family : int {
    near_parallel_edges = static_cast<int>(tri::Kind::count),  ///< an edge of Q almost parallel and close to one of P
    touching_edge,    ///< Q meets P exactly along a piece of an edge line (one side, or coplanar outside)
    duplicated_face,  ///< Q is P in another vertex order, or P with a few coordinates moved by 1 ulp
    orders36,         ///< one hard case in all 36 vertex orders and both argument orders (72 cases per base)
    end
};
inline constexpr int kFamilies = static_cast<int>(Family::end);

inline std::string family_name(int f) {
    if (f < static_cast<int>(tri::Kind::count)) return tri::name(static_cast<tri::Kind>(f));
    switch (static_cast<Family>(f)) {
    case Family::near_parallel_edges: return "near_parallel_edges";
    case Family::touching_edge: return "touching_edge";
    case Family::duplicated_face: return "duplicated_face";
    case Family::orders36: return "orders36";
    default: return "?";
    }
}

/// A full-precision triangle in [-1, 1]^3 with nonzero area in double.
inline Tri real_triangle(Rng& r) {
    for (;;) {
        Tri t = {r.vec(-1, 1), r.vec(-1, 1), r.vec(-1, 1)};
        if ((t[1] - t[0]).cross(t[2] - t[0]).squaredNorm() > 1e-6) return t;
    }
}

inline double signed_offset(Rng& r) {
    static const double offs[] = {0.0, 1e-15, 1e-12, 1e-9, 1e-6};
    return offs[r.integer(0, 4)] * (r.coin() ? 1.0 : -1.0);
}

/// Q's first edge runs along P's edge (a, b) at distance 0 … 1e-6 (in P's plane or out of it) and turned
/// by an angle 0 … 1e-6; Q's third vertex goes across P's plane, onto it, or away from it.
inline Pair gen_near_parallel_edges(Rng& r) {
    Pair x;
    const bool ints = r.coin();
    x.p = ints ? tri::int_triangle(r) : real_triangle(r);
    const int i = r.integer(0, 2);
    const V a = x.p[i], b = x.p[(i + 1) % 3], e = b - a;
    const V n = e.cross(x.p[(i + 2) % 3] - a).normalized();
    const V w = n.cross(e).normalized();  // in P's plane, perpendicular to the edge
    const V off_dir = r.coin() ? n : w;
    const double len = e.norm();
    V q0 = a + r.dyadic(-8, 8) * e, q1 = a + r.dyadic(8, 24) * e;  // exact on the line for integer P
    q0 += signed_offset(r) * len * off_dir;
    q1 += signed_offset(r) * len * (r.coin() ? off_dir : (r.coin() ? n : w));
    const double side = r.coin() ? 1.0 : -1.0;
    const int mode = r.integer(0, 2);
    V q2 = a + r.dyadic(0, 16) * e;
    if (mode == 0) q2 += side * len * n;                     // Q stands on the edge
    else if (mode == 1) q2 += side * len * w;                // Q in (near) P's plane, inside or outside
    else q2 += side * len * n + r.vec(-len, len);            // anywhere above or below
    x.q = {q0, q1, q2};
    if (r.coin(0.3)) std::swap(x.p, x.q);
    return x;
}

/// Q's edge (q0, q1) lies exactly on the line of P's edge (a, b), overlapping the edge or not; Q lies on one
/// side of P's plane, or in P's plane on the outside of that edge: the triangles touch along a segment,
/// at a point, or not at all, never crossing.
inline Pair gen_touching_edge(Rng& r) {
    Pair x;
    x.p = tri::int_triangle(r, 6);
    const int i = r.integer(0, 2);
    const V a = x.p[i], b = x.p[(i + 1) % 3], c = x.p[(i + 2) % 3], e = b - a;
    const V n = e.cross(c - a);  // integer: exact
    const V q0 = a + r.dyadic(-20, 20) * e, q1 = a + r.dyadic(-4, 36) * e;
    V q2 = a + r.dyadic(-8, 24) * e;
    const int mode = r.integer(0, 2);
    const double side = r.coin() ? 1.0 : -1.0;
    if (mode == 0) q2 += side * r.dyadic(1, 16) * n;                              // standing on the edge line
    else if (mode == 1) q2 -= r.dyadic(1, 16) * (c - a);                          // coplanar, outside the edge
    else q2 += side * r.dyadic(1, 16) * n - r.dyadic(0, 16) * (c - a);            // leaning outwards
    x.q = {q0, q1, q2};
    if (r.coin()) std::swap(x.p, x.q);
    return x;
}

/// Q = P in some vertex order; or with up to three coordinates moved by ±1 ulp; or both orders of an
/// integer triangle and its copy moved along an axis by one sixteenth (parallel duplicates).
inline Pair gen_duplicated_face(Rng& r) {
    Pair x;
    x.p = r.coin() ? tri::int_triangle(r) : real_triangle(r);
    const int* perm = tri::kPerm[r.integer(0, 5)];
    x.q = {x.p[perm[0]], x.p[perm[1]], x.p[perm[2]]};
    const int mode = r.integer(0, 3);
    if (mode == 1 || mode == 2) {
        for (int k = 0, m = r.integer(1, 3); k < m; ++k) {
            double& c = x.q[r.integer(0, 2)][r.integer(0, 2)];
            c = std::nextafter(c, (r.coin() ? 1.0 : -1.0) * std::numeric_limits<double>::infinity());
        }
    } else if (mode == 3) {
        const int k = r.integer(0, 2);
        const double d = r.dyadic(-1, 1);
        for (auto& v : x.q) v[k] += d;
    }
    return x;
}

/// One pair of the family f (not orders36, which the driver expands from a base pair).
inline Pair generate(int f, Rng& r) {
    if (f < static_cast<int>(tri::Kind::count)) return tri::generate(static_cast<tri::Kind>(f), r);
    switch (static_cast<Family>(f)) {
    case Family::near_parallel_edges: return gen_near_parallel_edges(r);
    case Family::touching_edge: return gen_touching_edge(r);
    case Family::duplicated_face: return gen_duplicated_face(r);
    default: return tri::gen_random(r);
    }
}

/// The base pair of the orders36 family: drawn from the exact-construction families, where vertex order is
/// most likely to matter (touching, coplanar, degenerate, duplicated).
inline Pair orders36_base(Rng& r) {
    static const int bases[] = {static_cast<int>(tri::Kind::coplanar),      static_cast<int>(tri::Kind::shared_edge),
                                static_cast<int>(tri::Kind::vertex_on_face), static_cast<int>(tri::Kind::edge_on_edge),
                                static_cast<int>(tri::Kind::zero_area),      static_cast<int>(tri::Kind::grid),
                                static_cast<int>(tri::Kind::vertex_near_plane), static_cast<int>(Family::touching_edge),
                                static_cast<int>(Family::duplicated_face),   static_cast<int>(Family::near_parallel_edges)};
    return generate(bases[r.integer(0, 9)], r);
}

/// Variant k in [0, 72) of a base pair: P in order k % 6, Q in order (k / 6) % 6, swapped when k ≥ 36.
inline Pair reorder(const Pair& x, int k) {
    const int* a = tri::kPerm[k % 6];
    const int* b = tri::kPerm[(k / 6) % 6];
    Pair y{{x.p[a[0]], x.p[a[1]], x.p[a[2]]}, {x.q[b[0]], x.q[b[1]], x.q[b[2]]}};
    if (k >= 36) std::swap(y.p, y.q);
    return y;
}

}  // namespace cdkit::accuracy
