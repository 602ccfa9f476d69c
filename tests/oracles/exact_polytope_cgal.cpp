// The exact polytope referee (exact_polytope.hpp): the only TU of its binaries that includes CGAL's optimisation
// headers. Distance: CGAL's Polytope_distance_d (Gärtner & Schönherr's exact QP solver, CGAL User Manual,
// "Optimal Distances") over a homogeneous kernel whose ring type is CGAL::Gmpzf, arbitrary-precision binary
// floating point: sums and products of doubles are exact in it, so the posed vertices R·x + t are exact and the
// solver's answer (a ratio of two Gmpzf) is the exact squared distance. Depth: six exact LPs (CGAL's
// solve_linear_program with Gmpzf), min over |u|∞ = 1 of max_a u·a − min_b u·b.
#include "oracles/exact_polytope.hpp"

#include <CGAL/Gmpzf.h>
#include <CGAL/Homogeneous.h>
#include <CGAL/Polytope_distance_d.h>
#include <CGAL/Polytope_distance_d_traits_3.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace cdkit::test::exact {
namespace {

using ET = CGAL::Gmpzf;
using K = CGAL::Homogeneous<ET>;
using Point = K::Point_3;
using Traits = CGAL::Polytope_distance_d_traits_3<K, ET, ET>;
using Distance = CGAL::Polytope_distance_d<Traits>;
using Coords = std::array<ET, 3>;

/// R·x + t, exactly.
std::vector<Coords> posed(const std::vector<Vec3<double>>& v, const Transform<double>& p) {
    std::vector<Coords> out;
    out.reserve(v.size());
    for (const auto& x : v) {
        Coords c;
        for (int i = 0; i < 3; ++i)
            c[std::size_t(i)] = ET(p.R(i, 0)) * ET(x[0]) + ET(p.R(i, 1)) * ET(x[1]) + ET(p.R(i, 2)) * ET(x[2]) +
                                ET(p.t[i]);
        out.push_back(c);
    }
    return out;
}

std::vector<Point> points(const std::vector<Coords>& c) {
    std::vector<Point> out;
    out.reserve(c.size());
    for (const auto& x : c) out.emplace_back(x[0], x[1], x[2], ET(1));
    return out;
}

double ratio(const ET& num, const ET& den) {
    // Gmpzf's to_double rounds each; their quotient is within ~2ε of the exact ratio.
    return CGAL::to_double(num) / CGAL::to_double(den);
}

/// min ca − cb over u with u_k = s, |u_m| ≤ 1, ca ≥ u·a_i, cb ≤ u·b_j (variables u0 u1 u2 ca cb).
CGAL::Quotient<ET> depth_along_face(const std::vector<Coords>& a, const std::vector<Coords>& b, int k, int s) {
    CGAL::Quadratic_program<ET> lp(CGAL::SMALLER, false, ET(0), false, ET(0));
    int row = 0;
    for (const auto& x : a) {  // u·a − ca ≤ 0
        for (int j = 0; j < 3; ++j) lp.set_a(j, row, x[std::size_t(j)]);
        lp.set_a(3, row, ET(-1));
        lp.set_b(row, ET(0));
        ++row;
    }
    for (const auto& x : b) {  // cb − u·b ≤ 0
        for (int j = 0; j < 3; ++j) lp.set_a(j, row, -x[std::size_t(j)]);
        lp.set_a(4, row, ET(1));
        lp.set_b(row, ET(0));
        ++row;
    }
    for (int j = 0; j < 3; ++j) {
        const ET lo = j == k ? ET(s) : ET(-1), hi = j == k ? ET(s) : ET(1);
        lp.set_l(j, true, lo);
        lp.set_u(j, true, hi);
    }
    lp.set_c(3, ET(1));
    lp.set_c(4, ET(-1));
    const auto sol = CGAL::solve_linear_program(lp, ET());
    // Bounded and feasible by construction (any u with cb = min u·b, ca = max u·a).
    return sol.objective_value();
}

}  // namespace

PolytopePairAnswer exact_polytope_pair(const std::vector<Vec3<double>>& a, const Transform<double>& pose_a,
                                       const std::vector<Vec3<double>>& b, const Transform<double>& pose_b,
                                       bool with_depth) {
    const std::vector<Coords> ca = posed(a, pose_a), cb = posed(b, pose_b);
    const std::vector<Point> pa = points(ca), pb = points(cb);
    const Distance pd(pa.begin(), pa.end(), pb.begin(), pb.end());
    PolytopePairAnswer r;
    const ET num = pd.squared_distance_numerator(), den = pd.squared_distance_denominator();
    r.intersect = CGAL::is_zero(num);
    r.squared_distance = r.intersect ? 0.0 : ratio(num, den);
    r.distance = std::sqrt(r.squared_distance);
    if (with_depth && r.intersect) {
        CGAL::Quotient<ET> best;
        bool first = true;
        for (int k = 0; k < 3; ++k)
            for (int s : {-1, 1}) {
                const CGAL::Quotient<ET> v = depth_along_face(ca, cb, k, s);
                if (first || v < best) best = v, first = false;
            }
        r.depth_known = true;
        r.touching = CGAL::is_zero(best.numerator());
        r.depth_inf = ratio(best.numerator(), best.denominator());
    }
    return r;
}

bool exact_direction_separates(const std::vector<Vec3<double>>& a, const Transform<double>& pose_a,
                               const std::vector<Vec3<double>>& b, const Transform<double>& pose_b,
                               const Vec3<double>& n) {
    const std::vector<Coords> ca = posed(a, pose_a), cb = posed(b, pose_b);
    const ET n0(n[0]), n1(n[1]), n2(n[2]);
    auto along = [&](const Coords& x) { return n0 * x[0] + n1 * x[1] + n2 * x[2]; };
    ET top = along(ca.front());
    for (const auto& x : ca) top = std::max(top, along(x));
    for (const auto& x : cb)
        if (along(x) < top) return false;
    return true;
}

}  // namespace cdkit::test::exact
