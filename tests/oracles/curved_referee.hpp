#pragma once
// An independent referee for convex pairs with curved shapes (issue 37, "independent oracles"): spheres, capsules,
// cylinders, cones, ellipsoids, rounded boxes (Inflated<Box>), boxes and hulls, each posed by a double rotation
// and translation, judged in MPFR arithmetic (269 bits) from support functions written here, sharing no code with
// cdkit's shapes or GJK (the MPFR headers are compiled only in curved_referee_mpfr.cpp).
//
// Method: support-function duality (e.g. Rockafellar, Convex Analysis, §13 and §16; Gilbert, Johnson & Keerthi,
// IEEE J. Robotics and Automation 4(2), 1988, §II): with D = B − A (the Minkowski difference, h_D(u) =
// h_B(u) + h_A(−u)), dist(A, B) = dist(0, D) = max over unit u of −h_D(−u), and every point of conv{s_D(u_i)}
// lies in D. So
//  * SEPARATED is certified by a unit u with gap(u) = −h_D(−u) = min_b u·b − max_a u·a > 0; then
//    dist ∈ [gap(u), |v|] for any v in the hull of support points of D;
//  * INTERSECTING is certified by four support points of D whose tetrahedron holds the origin strictly: the origin
//    is then a convex combination of points b_i − a_i, so Σλ_i a_i = Σλ_i b_i is a common point. The distance from
//    the origin to the tetrahedron's faces, less its error bound, is a certified lower bound of the penetration
//    depth (a ball that large lies inside D);
//  * otherwise UNDECIDED (the search failed, or the pair touches within the error bounds): counted by the callers,
//    never dropped.
// The search for the certificates is a minimum-norm-point iteration over support points (Gilbert–Johnson–Keerthi's
// outer loop), with the minimum-norm point of each simplex found by trying every sub-simplex (no Johnson recursion,
// no cached determinants): 269-bit arithmetic makes the degeneracies that a double GJK must guard against harmless.
// Where the origin lies on a flat simplex that no further support point lifts (coincident shapes symmetric about
// it), intersection is certified instead by six points ±c·e_k (c = 1e-30·Σ) each certified inside B − A: their
// octahedron holds the ball of radius c/√3. It may start from a hint (cdkit's answer's normal: the certificate is checked independently of where the search
// started).
//
// Error bounds: the poses and shape parameters are the given doubles, taken exactly; each support point is computed
// in 269-bit arithmetic (relative rounding 2^-268 ≈ 2e-81 per operation), so every computed point of a shape lies
// within about 1e-78 of the scene's scale Σ (the largest |t| plus bounding radius) of the true one. The referee
// counts an evaluation error of 1e-70·Σ (eps below) in every compared quantity; the tetrahedron test adds the
// conditioning of each face (its longest edge over its smallest altitude) to that. Pairs closer to touching than
// that are undecided.
#include <cdkit/core/math.hpp>

#include <vector>

namespace cdkit::test::curved {

/// The shapes the referee knows, in their local frames as convex_shapes.hpp defines them (centred, axis z).
enum class ShapeKind {
    sphere,       ///< a = radius
    box,          ///< half extents a, b, c
    capsule,      ///< a = radius, b = half length of the z segment
    cylinder,     ///< a = radius, b = half height
    cone,         ///< a = base radius (base disc at z = −b), b = half height (apex at z = +b)
    ellipsoid,    ///< radii a, b, c
    rounded_box,  ///< the box of half extents a, b, c plus the ball of radius r (Minkowski sum)
    hull          ///< conv(*vertices)
};

/// One shape's description; `vertices` (hull only) must outlive the call.
struct ShapeSpec {
    ShapeKind kind = ShapeKind::sphere;
    double a = 0, b = 0, c = 0, r = 0;
    const std::vector<Vec3<double>>* vertices = nullptr;
};

enum class Verdict { separated, intersecting, undecided };

/// The referee's answer for the posed pair.
struct CurvedAnswer {
    Verdict verdict = Verdict::undecided;
    /// separated: dist(A, B) ∈ [lower, upper], both rounded outward by the error bound (lower > 0).
    double lower = 0, upper = 0;
    /// intersecting: a certified lower bound of the Euclidean penetration depth (> 0): a ball of that radius about
    /// the origin lies in B − A.
    double depth_lower = 0;
    int iterations = 0;  ///< support-point rounds of the search
};

/// Judges A (posed by pa) against B (posed by pb). `hint`: a direction from A towards B to start from (any
/// vector; zero: the centres' difference).
[[nodiscard]] CurvedAnswer curved_referee(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b,
                                          const Transform<double>& pb, const Vec3<double>& hint);

/// Whether the penetration depth of the pair exceeds `rho`: +1 certified deeper than rho (the six points ±√3·rho
/// along the axes lie in B − A: their octahedron holds the ball of radius rho); −1 certified shallower than
/// √3·rho, or apart (one of those points lies outside B − A); 0 undecided. The L∞-style band of the exact
/// polytope judge (depth_inf ∈ [δ, √3·δ]).
[[nodiscard]] int depth_exceeds(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b,
                                const Transform<double>& pb, double rho);

/// The point of A (posed) furthest along u and its support value, in double (rounded from the 269-bit values):
/// for the referee's own tests.
[[nodiscard]] Vec3<double> support_point(const ShapeSpec& s, const Transform<double>& pose, const Vec3<double>& u);

}  // namespace cdkit::test::curved
