#pragma once
/// \file GJK ray cast: the first λ in [0, λ_max] at which the point x = λ·r enters a convex set C known by its
/// support map (G. van den Bergen, "Ray Casting against General Convex Objects with Application to Continuous
/// Collision Detection", 2004). For two translating shapes C is A − B at their start poses and r the relative
/// motion, so λ is the time of impact: the shape cast.
///
/// One GJK loop, on the vectors w = x − p from C's support points p to x. v is the vector from the simplex's point
/// nearest x to x. Each step takes p, C's support point along v: when v·(x − p) > 0, the plane through p orthogonal
/// to v has all of C behind it and x in front, so the ray cannot enter C before it reaches that plane: λ moves to
/// the plane (a lower bound, so λ never passes the true entry) and the simplex's w are re-aimed at the new x. Then p
/// joins the simplex and v becomes its nearest point. The loop ends when |v| ≤ tolerance (x is within the
/// tolerance of C: a hit at λ), when the ray runs parallel to or away from a separating plane (a miss), or when λ
/// passes λ_max (a miss within the step). Unlike advancement with a fresh distance query per step, the simplex
/// carries over, so the whole cast costs about one GJK distance query.

#include "cdkit/narrowphase/gjk/detail/simplex_solver.hpp"

#include <cmath>

namespace cdkit::detail {

struct GjkRayCastResult {
    enum class End { hit, miss, capped };
    End end = End::miss;
    double lambda = 0;  ///< the hit's λ (a lower bound on the entry); the last certified λ when capped
    /// The simplex's nearest point as weights over the support pairs: Σ w_k·a_k and Σ w_k·b_k (a_k − b_k = p_k).
    Vec3<double> point_a = Vec3<double>::Zero(), point_b = Vec3<double>::Zero();
    Vec3<double> normal = Vec3<double>::Zero();  ///< unit v at the end (from the set towards x), or the last plane's
    int iterations = 0;
};

/// `support(d, a, b)` sets a and b with a − b the support point of C along d. `start` is any vector not zero
/// (the first search direction); `tolerance` > 0.
template <class Support>
[[nodiscard]] GjkRayCastResult gjk_ray_cast(Support&& support, const Vec3<double>& r, const Vec3<double>& start,
                                            double lambda_max, double tolerance, int max_iterations) noexcept {
    GjkRayCastResult out;
    GjkSimplex<double> s;
    s.size = 0;
    Vec3<double> x = Vec3<double>::Zero(), v = start, plane = Vec3<double>::Zero();
    auto finish = [&](GjkRayCastResult::End end) {
        out.end = end;
        SimplexSolver<double>::sliver_weights(s, v);  // needle triangles' weights, as GJK's witnesses
        for (int k = 0; k < s.size; ++k) {
            out.point_a += s.lambda[std::size_t(k)] * s.v[std::size_t(k)].a;
            out.point_b += s.lambda[std::size_t(k)] * s.v[std::size_t(k)].b;
        }
        const Vec3<double> dir = v.squaredNorm() > 0 ? v : plane.squaredNorm() > 0 ? plane : Vec3<double>(-r);
        out.normal = dir.squaredNorm() > 0 ? Vec3<double>(dir.normalized()) : Vec3<double>::Zero();
        return out;
    };
    const double tol2 = tolerance * tolerance;
    for (out.iterations = 1; out.iterations <= max_iterations; ++out.iterations) {
        if (s.size > 0 && v.squaredNorm() <= tol2) return finish(GjkRayCastResult::End::hit);
        Vec3<double> a, b;
        support(v, a, b);
        const Vec3<double> w = x - (a - b);
        const double vw = v.dot(w);
        // x stops half the tolerance before the plane (and its rounding), as the advancement does: λ stays a lower
        // bound under rounding too, and a face met head-on ends with |v| ≈ tolerance / 2.
        const double vn = v.norm(), vr = v.dot(r);
        const double gap = vw * (1 - 1e-12) - 0.5 * tolerance * vn;
        // More than the tolerance in front of a plane that the ray runs parallel to or away from: a miss. (Nearer,
        // x may be within the tolerance of C already: GJK goes on until |v| says which.)
        if (vw > tolerance * vn && !(vr < 0)) return finish(GjkRayCastResult::End::miss);
        const bool advanced = gap > 0 && vr < 0;
        if (advanced) {
            // The plane v·y = v·p: x(λ') = λ'·r reaches it at λ' = λ − v·w / v·r (> λ).
            out.lambda -= gap / vr;
            if (!(out.lambda <= lambda_max)) return finish(GjkRayCastResult::End::miss);
            x = out.lambda * r;
            plane = v;
            for (int k = 0; k < s.size; ++k)
                s.v[std::size_t(k)].w = x - (s.v[std::size_t(k)].a - s.v[std::size_t(k)].b);
        }
        bool known = false;  // the support point is already a vertex: adding it again would make the simplex flat
        for (int k = 0; k < s.size; ++k) known = known || (s.v[std::size_t(k)].a == a && s.v[std::size_t(k)].b == b);
        if (known && !advanced) return finish(GjkRayCastResult::End::capped);  // no progress left: conservative
        if (!known && s.size == 4) return finish(GjkRayCastResult::End::capped);  // a full simplex not holding x
        if (!known) {
            GjkVertex<double>& added = s.v[std::size_t(s.size++)];
            added.w = x - (a - b);
            added.a = a;
            added.b = b;
        }
        if (SimplexSolver<double>::solve(s, v)) {  // x inside the tetrahedron, so inside C: weights of x in it
            Eigen::Matrix3d m;
            for (int k = 0; k < 3; ++k) m.col(k) = s.v[std::size_t(k + 1)].w - s.v[0].w;
            const Vec3<double> l = m.fullPivLu().solve(Vec3<double>(-s.v[0].w));
            s.lambda = {1 - l.sum(), l.x(), l.y(), l.z()};
            v.setZero();
            return finish(GjkRayCastResult::End::hit);
        }
    }
    return finish(GjkRayCastResult::End::capped);
}

}  // namespace cdkit::detail
