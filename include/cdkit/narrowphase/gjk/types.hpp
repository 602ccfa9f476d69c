#pragma once
/// \file GJK's public types: settings, the caller-owned warm-start cache, the simplex and the result of
/// `gjk_distance` / `gjk_intersect` (gjk/query.hpp). The algorithm and its papers: narrowphase/gjk.hpp.

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {

/// Tuning of a GJK query. Tolerances are relative; GJK scales them with the size of the shapes.
template <class S = double> struct GjkSettings {
    /// Iteration cap (then `max_iterations`, with the best bound found). GJK converges linearly on curved shapes,
    /// slowest where both are needles: in the 1M-case hard count (docs/convex.md, "Hard cases") two ellipsoids
    /// 1e-7 wide near contact took up to 181 iterations in double (6 cases above 128, the cap FCL uses),
    /// every other query at most 113. Only such pairs come near it; it still bounds every query.
    int max_iterations = 256;
    /// Stop when the distance upper bound |v| is within rel_tolerance·|v| of the lower bound.
    S rel_tolerance = std::max(S(1e-10), S(64) * std::numeric_limits<S>::epsilon());
    /// Distances within touch_factor·ε·(size of D) of zero count as touching.
    S touch_factor = S(256);
    /// Boolean queries with a cache: accept a separating plane only once its gap is at least this fraction
    /// of the distance upper bound (0 = at the first separating plane), so that the direction cached for the
    /// next frame still separates after a small motion. No effect on the answer, only on the work split.
    S warm_exit_quality = S(0.5);
    /// Cold boolean queries (`gjk_intersect` without a cache): Nesterov momentum on the search direction in
    /// iterations 2 … momentum_iterations (Montaut et al. 2022; ≤ 1 = plain GJK), on pairs without margins. It cut the iterations of close
    /// curved pairs by up to 3.7× in the P3 benchmark; past a few iterations it mostly cost overlapping
    /// cylinders and cones extra ones, hence the cap. Only the work depends on it, never the answer.
    int momentum_iterations = 5;
    /// Cold boolean queries on shapes with bounding balls (`HasBoundingBalls`: every primitive and
    /// `ConvexPolyhedron`), and cold `gjk_distance_within` (its "separated" needing balls apart by more than its
    /// bound): before any support query, answer "separated" when the balls about the two centres
    /// that contain the shapes are disjoint, and "intersecting" when the balls that the shapes contain
    /// overlap, each beyond a rounding slack (256ε times the magnitudes involved). Such answers report
    /// `iterations == 0`; a separated one has the ball gap as its distance (a lower bound), the centre line
    /// as its normal and the balls' points on it as `point_a` / `point_b` (the planes through them orthogonal
    /// to the normal separate the shapes; they are points of the balls, not of the shapes).
    bool bounding_ball_test = true;
    /// Cold boolean queries on pairs with bounding balls where a shape has a containment test
    /// (`HasContainmentTest`: box, cylinder, cone, convex polyhedron): answer "intersecting" (no simplex) when
    /// the first support point of the other shape (along the centre line) lies inside it beyond a rounding slack
    /// (`iterations == 1`; see `detail::containment_decides`) or, for two shapes with cheap tests and curved
    /// cores (cylinder, cone), when a later round's support point does
    /// (`detail::loop_containment_decides`). Only the work depends on it, never whether the pair collides;
    /// where the loop would end "touching" (within its tolerance of contact) a point proven strictly inside
    /// makes it "intersecting". A hull's location (`HasPointLocation`) also names the face
    /// plane it found the point beyond, which `candidate_axes` tries.
    bool containment_test = true;
    /// Cold boolean queries where a shape names candidate axes (`HasCandidateAxes`: box, cone; a convex
    /// polyhedron's face from its point location, with `containment_test`): when the first support pair decides
    /// nothing, try the face normal of each such shape towards the other's first support point, and where both
    /// name edges (`HasCandidateEdges`: boxes) the cross product of their nearest edges, with the loop's plane
    /// test (one support pair each) before the loop. A plane found there is an ordinary early exit (`normal`,
    /// `distance`, `point_a` / `point_b` as for any plane; `iterations` 2 to 4). The work and the plane reported
    /// depend on it, the status does not.
    bool candidate_axes = true;
    /// Distance queries in double (`gjk_distance`; booleans never, nor `penetration()`, which runs its own loop):
    /// a separated answer closer than 32ε·m / rel_tolerance (2ε·m / rel_tolerance for two polytope cores,
    /// `HasPolytopeCore`), m = |t_rel|₁ + the largest |a − b| seen, is computed again by GJK in long double from its
    /// final simplex (`detail::refine_near_contact`), where the double loop's rounding exceeds its tolerance (docs/
    /// convex.md, "Near contact"); so is one whose loop stopped with a gap |v| − v·w/|v| above 4× the tolerance
    /// (a repeated point, no progress or the rounding floor: needle pairs, whose Minkowski difference is so thin
    /// that v·w's rounding, ε·size², hides which end is nearer). A refinement costs microseconds with x87 long
    /// double (more where long double is software quad); a small rel_tolerance makes more queries refine. Only
    /// where long double is wider than double. Rotations should be orthonormal to working precision either way:
    /// the loop's frame takes R_aᵀ for R_a's inverse.
    bool refine_near_contact = true;
};

/// Caller-owned warm start (van den Bergen 1999 §5, "frame coherence"): the last final simplex, as the
/// search directions that produced it (in A's frame) and its support points on the two cores (each in its
/// own shape's local frame). The next query rebuilds the simplex from the stored points under the new
/// poses, without a support query: they are still points of A and B, so the rebuilt simplex lies in A − B
/// and every bound GJK derives from it stays valid; only its closeness to the answer depends on coherence.
/// The points are only reused for the same two shape objects (their addresses are kept); for others the
/// directions are re-evaluated. Keep one per shape pair, and reset it (`size = 0`) when a shape's geometry
/// changes in place. A query reads and updates it. Not shared between threads.
template <class S = double> struct GjkCache {
    std::array<Vec3<S>, 4> directions{};
    int size = 0;
    std::array<Vec3<S>, 4> point_a{}, point_b{};  ///< core support points, local frames of A and B
    const void* shape_a = nullptr;                ///< the shapes the points belong to
    const void* shape_b = nullptr;
    /// Start vertices for shapes with a hinted support query (`HintedSupport`: polyhedra), last frame's
    /// support vertices; they only shorten the hill climbing, any value is safe.
    std::uint32_t hint_a = std::uint32_t(-1), hint_b = std::uint32_t(-1);
};

/// One simplex vertex: w = a − b with a ∈ A, b ∈ B, found as the support of A − B along d
/// (all in A's frame).
template <class S> struct GjkVertex {
    Vec3<S> w, a, b, d;
    Vec3<S> b_local;  ///< the same point of B in B's own frame (kept exactly for the warm start)
};

/// The simplex GJK ended with, its barycentric weights and size (1..4), in A's local frame.
template <class S> struct GjkSimplex {
    std::array<GjkVertex<S>, 4> v;  ///< only the first `size` are meaningful
    std::array<S, 4> lambda{};
    int size = 0;
    /// User-provided so that `GjkSimplex{}` (and every GjkResult) does not zero the 480 bytes of vertices:
    /// that memset was a quarter of a one-iteration boolean query.
    GjkSimplex() noexcept {}
};

/// Result of `gjk_distance` / `gjk_intersect`.
template <class S> struct GjkResult {
    GjkStatus status = GjkStatus::degenerate;
    int iterations = 0;
    /// Separation distance (≥ 0; 0 when touching or intersecting). `gjk_intersect` only sets it when it
    /// had to converge; after an early "separated" exit it holds a lower bound (> 0).
    S distance = S(0);
    /// Closest points on A and on B in the world frame (valid when separated or touching). After
    /// gjk_intersect's early exit: A's and B's extreme points along `normal` (the planes through them
    /// orthogonal to `normal` separate the shapes), not the closest points; after its bounding-ball exit
    /// (`iterations == 0`, see GjkSettings::bounding_ball_test) the balls' extreme points along `normal`.
    Vec3<S> point_a = Vec3<S>::Zero(), point_b = Vec3<S>::Zero();
    /// Unit direction from A towards B in the world frame (valid when separated; after gjk_intersect's early
    /// exit it is a separating direction, not necessarily the closest-point direction).
    Vec3<S> normal = Vec3<S>::Zero();
    /// Final simplex on the cores, in A's local frame (used by EPA).
    GjkSimplex<S> simplex{};
    /// `is_colliding(status)`: touching or intersecting.
    bool colliding = false;
};

}  // namespace cdkit
