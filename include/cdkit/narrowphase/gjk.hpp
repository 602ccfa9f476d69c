#pragma once
/// \file GJK: boolean intersection and separation distance between two support-mapped convex shapes.
///
/// Gilbert, Johnson, Keerthi, "A fast procedure for computing the distance between complex objects in
/// three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988; with the robustness measures of
/// van den Bergen, "A fast and robust GJK implementation for collision detection of convex objects",
/// J. Graphics Tools 4(2), 1999 (termination on the lower bound v·w, progress check, duplicate support
/// points) and the degenerate-simplex discussion of Montaut et al., "Collision detection accelerated: an
/// optimization perspective", RSS 2022.
///
/// GJK walks the Minkowski difference D = A − B (never built): the shapes intersect iff 0 ∈ D and their
/// distance is min_{x∈D} |x|. Each iteration queries the support of D opposite to the current closest
/// point v, adds it to a simplex of ≤ 4 points, and replaces v by the simplex's point closest to the
/// origin (computed with Voronoi-region tests, reducing the simplex to the face/edge/vertex that holds v).
/// Shapes with a margin (spheres, capsules, `Inflated`) run on their cores; the margins are subtracted at
/// the end, which makes sphere and capsule results exact rather than asymptotic.
///
/// Cost measures (after Montaut et al. 2022, whose GJK beat libccd's by avoiding copies and stopping
/// boolean queries at the first separating plane): the sub-simplex step only selects indices and weights and
/// moves the surviving vertices once, when the step is accepted (no simplex copy per iteration, no per-face
/// copies in the tetrahedron case); the boolean query tests every support point for a separating plane,
/// the first one included; the warm start rebuilds the last simplex from its stored support points without
/// support queries (they are points of the shapes, so all bounds stay certified).
///
/// Cold boolean queries (`gjk_intersect` without a cache) take a leaner loop (`gjk_intersect_cold`): the
/// first support pair in the world frame along the centre line (a distant pair is decided without forming the
/// relative pose), squared plane tests, and Nesterov momentum on the search direction in the first few
/// iterations (Montaut et al. 2022, above), which the boolean certificates make safe: a plane is proven by
/// the direction actually queried, overlap by four support points around the origin. Before any support
/// query it compares the centre distance with the shapes' bounding balls (`HasBoundingBalls`; disjoint outer
/// balls prove separation, overlapping inner balls prove overlap, beyond a rounding slack); after the first
/// support pair it tests whether either point lies strictly inside the other shape (`HasContainmentTest`: a
/// point of one shape inside the other proves overlap without a tetrahedron; a hull locates the point by a walk,
/// `HasPointLocation`); then, for shapes that name candidate axes (`HasCandidateAxes`: a box's or a cone's face
/// normal towards the other shape's first support point, and the cross product of two boxes' nearest edges,
/// `HasCandidateEdges`; a hull's face whose plane its location found the point beyond), it gives those
/// directions the plane test before the loop (on close box pairs one of them is usually the separating axis).
/// Its tetrahedron step uses that the newest point is vertex 3. A warm boolean (with a cache) first gives the
/// cached separating direction the same world-frame plane test (`warm_direction_separates`).
///
/// Accuracy on curved shapes: near contact the support points cluster and the triangle step meets slivers
/// whose rounded normal can put v below the simplex (|v| then under-estimates the distance and the gap test
/// passes early); distance queries estimate that rounding and redo such steps in a wider type (`wider_t`),
/// as do the "no progress" and "repeated vertex" exits. Per-call cost: no zero-filled result, rotations and
/// vector arithmetic written out (they were out-of-line Eigen calls at -O2), hill-climbing hints for polyhedra
/// kept per query and, in the cache, per pair.
///
/// Certified separation: "separated" claims a separating plane, so it is only answered with one — a support
/// plane bound v·w/|v| above the touching tolerance (van den Bergen 1999). GJK's exits on |v| (gap test,
/// repeated point, no progress) carry none; near contact they could answer "separated" for pairs that overlap
/// by 1e-12 … 1e-9 of their size. Such exits continue with wide-type sub-simplex steps (`certify_separation`)
/// and answer `touching` when that decides nothing (docs/convex.md, "Certified separation").
///
/// All queries are noexcept, const on their inputs and thread-safe; the only mutable state is the
/// caller-owned `GjkCache`.

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
    /// `ConvexPolyhedron`): before any support query, answer "separated" when the balls about the two centres
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

namespace detail {

/// Closest point to the origin on the simplex `s` (point, segment, triangle or tetrahedron), computed
/// without touching `s`: the result names the vertices of the smallest sub-simplex holding that point (by
/// index into `s`, ascending) with their barycentric weights. The caller applies it only when it accepts
/// the step, so GJK's "no progress: keep the previous simplex" rule needs no copy of the simplex, and the
/// tetrahedron case evaluates its faces in place instead of copying each into a temporary simplex.
template <class S> struct SimplexSelection {
    std::array<int, 4> idx{};
    std::array<S, 4> lambda{};
    int size = 0;
    bool inside = false;  ///< origin inside a full-dimensional tetrahedron (v = 0, nothing dropped)
    Vec3<S> v = Vec3<S>::Zero();
    /// Triangle steps (size 3): |e1|²·|e2|² and |e1 × e2|² of the two edges the normal was built from, so that
    /// 1/sin² of their angle (the normal's rounding, see `triangle_step_unreliable`) costs no recomputation.
    S edges2 = S(0), normal2 = S(0);
};

template <class S> class SimplexSolver {
public:
    using Sel = SimplexSelection<S>;

    static void point(const GjkSimplex<S>& s, int i, Sel& r) noexcept {
        r.size = 1;
        r.idx[0] = i;
        r.lambda[0] = S(1);
        r.v = s.v[std::size_t(i)].w;
    }

    /// Segment i0–i1 (the closest point is measured from i0, as in the classic formulation).
    static void segment(const GjkSimplex<S>& s, int i0, int i1, Sel& r) noexcept {
        const Vec3<S>& p0 = s.v[std::size_t(i0)].w;
        const Vec3<S> d = s.v[std::size_t(i1)].w - p0;
        const S dd = d.squaredNorm();
        const S t = dd > S(0) ? -p0.dot(d) / dd : S(0);
        if (!(t > S(0))) { point(s, i0, r); return; }
        if (t >= S(1)) { point(s, i1, r); return; }
        r.size = 2;
        r.v = p0 + t * d;
        if (i0 < i1) {
            r.idx[0] = i0; r.idx[1] = i1; r.lambda[0] = S(1) - t; r.lambda[1] = t;
        } else {
            r.idx[0] = i1; r.idx[1] = i0; r.lambda[0] = t; r.lambda[1] = S(1) - t;
        }
    }

    /// Voronoi-region walk over triangle i0, i1, i2 (Ericson, "Real-Time Collision Detection", 2005,
    /// §5.1.5). On slivers the weights are as ill-conditioned as Ericson's products at a make them: callers
    /// that turn them into witness points fix them once, at the end (`sliver_weights`).
    static void triangle(const GjkSimplex<S>& s, int i0, int i1, int i2, Sel& r) noexcept {
        const Vec3<S>& a = s.v[std::size_t(i0)].w;
        const Vec3<S>& b = s.v[std::size_t(i1)].w;
        const Vec3<S>& c = s.v[std::size_t(i2)].w;
        const Vec3<S> ab = b - a, ac = c - a;
        const S d1 = -ab.dot(a), d2 = -ac.dot(a);
        if (d1 <= S(0) && d2 <= S(0)) { point(s, i0, r); return; }
        const S d3 = -ab.dot(b), d4 = -ac.dot(b);
        if (d3 >= S(0) && d4 <= d3) { point(s, i1, r); return; }
        const S vc = d1 * d4 - d3 * d2;
        if (vc <= S(0) && d1 >= S(0) && d3 <= S(0)) { segment(s, i0, i1, r); return; }
        const S d5 = -ab.dot(c), d6 = -ac.dot(c);
        if (d6 >= S(0) && d5 <= d6) { point(s, i2, r); return; }
        const S vb = d5 * d2 - d1 * d6;
        if (vb <= S(0) && d2 >= S(0) && d6 <= S(0)) { segment(s, i0, i2, r); return; }
        const S va = d3 * d6 - d5 * d4;
        if (va <= S(0) && (d4 - d3) >= S(0) && (d5 - d6) >= S(0)) { segment(s, i2, i1, r); return; }
        const S denom = va + vb + vc;
        // Squared edge lengths from the region tests' dot products (rounding only blurs which vertex is
        // chosen). The normal at a is kept unless a's angle is below 30° (then the largest is elsewhere).
        const S ab2 = d1 - d3, ac2 = d2 - d6;
        Vec3<S> n = ab.cross(ac);
        S nn = n.squaredNorm();
        r.edges2 = ab2 * ac2;
        const bool sliver = nn < S(0.25) * r.edges2;
        if (sliver) {
            n = stable_normal(b, c, ab, ac, ab2, ac2, ab2 + ac2 - S(2) * (d2 - d4), r.edges2);
            nn = n.squaredNorm();
        }
        r.normal2 = nn;
        auto best_edge = [&] {
            Sel e;
            S best = std::numeric_limits<S>::infinity();
            const int edges[3][2] = {{i0, i1}, {i1, i2}, {i0, i2}};
            for (const auto& ed : edges) {
                segment(s, ed[0], ed[1], e);
                const S dd = e.v.squaredNorm();
                if (dd < best) { best = dd; r = e; }
            }
            if (!(best < std::numeric_limits<S>::infinity())) segment(s, i0, i1, r);  // NaN data: any edge
        };
        // Degenerate (collinear) triangle that the region tests did not resolve: best edge.
        if (!(denom > S(0)) || !(nn > S(0))) { best_edge(); return; }
        // The plane projection is a point of the triangle only where it lies inside. On a sliver the
        // edge-region tests above are differences of products that cancel to rounding (a triangle 0.16 long and
        // 1e-15 wide: its squared area 4e-32 against products of 6e-4), so they may call a projection interior
        // that lies 1e-9 beyond a long edge: v then sits off the simplex, nearer than any of its points (|v|
        // 7 % below the distance between a capsule of radius 1e-9 and a box needle, in long double: a separated
        // pair answered intersecting). The projection's side of each edge, from the stable normal, decides it.
        // The plane projection is more accurate than the barycentric sum when v is small against a, b, c.
        const Vec3<S> v = n * (n.dot(a) / nn);
        if (sliver) {
            const bool inside = !(ab.cross(Vec3<S>(v - a)).dot(n) < S(0)) &&
                                !(Vec3<S>(c - b).cross(Vec3<S>(v - b)).dot(n) < S(0)) &&
                                !(Vec3<S>(a - c).cross(Vec3<S>(v - c)).dot(n) < S(0));
            if (!inside) { best_edge(); return; }
        }
        // Weights in ascending index order.
        const S l1 = vb / denom, l2 = vc / denom;
        const int ids[3] = {i0, i1, i2};
        const S lam[3] = {S(1) - l1 - l2, l1, l2};
        int o[3] = {0, 1, 2};
        if (ids[o[0]] > ids[o[1]]) std::swap(o[0], o[1]);
        if (ids[o[1]] > ids[o[2]]) std::swap(o[1], o[2]);
        if (ids[o[0]] > ids[o[1]]) std::swap(o[0], o[1]);
        r.size = 3;
        for (int k = 0; k < 3; ++k) { r.idx[std::size_t(k)] = ids[o[k]]; r.lambda[std::size_t(k)] = lam[o[k]]; }
        r.v = v;
    }

    /// Normal of triangle a, b, c as the cross product of the two edges at the vertex opposite the longest
    /// edge (its angle is the largest, ≥ 60°). The cross product of two edges rounds to a normal tilted by
    /// about ε over the sine of their angle; near contact on curved shapes GJK builds needles (two support
    /// points 1e-8 apart, the third 0.2 away), whose angle at the far vertex is ~1e-7: ab × ac from there
    /// tilted the plane enough to put |v| 1e-9 relative below the distance, even in long double.
    /// ab2, ac2, bc2: the squared edge lengths (approximate). The short edge is taken as c − b from the
    /// points, not ac − ab (which carries the rounding of the long edges).
    /// `edges2` receives the product of the two edges' squared lengths.
    static Vec3<S> stable_normal(const Vec3<S>& b, const Vec3<S>& c, const Vec3<S>& ab, const Vec3<S>& ac, S ab2,
                                 S ac2, S bc2, S& edges2) noexcept {
        if (bc2 >= ab2 && bc2 >= ac2) { edges2 = ab2 * ac2; return ab.cross(ac); }  // largest angle at a
        const Vec3<S> bc = c - b;
        if (ac2 >= ab2) { edges2 = ab2 * bc2; return ab.cross(bc); }  // at b: (b − a) × (c − b)
        edges2 = ac2 * bc2;
        return ac.cross(bc);  // at c: (c − a) × (c − b)
    }

    /// True when the origin's side of a face may be taken from side_o = −(n·p), n = e1 × e2, the face through p with
    /// edges e1, e2 (computed differences of the points). Its rounding is 16ε times the triple product's
    /// permanent, bounded by |e1|₁·|e2|₁·|p|₁ (Shewchuk, "Adaptive precision floating-point arithmetic and fast
    /// robust geometric predicates", DCG 1997: orient3d's stage-A bound is about 7ε·permanent); beyond it the sign
    /// is exact for those points. Within it, as a distance from the face's plane (bound/|n|), the rounding matters
    /// where it exceeds a few touching tolerances (1024ε·scale, scale the largest coordinate): on a sliver face
    /// (three support points along a needle 1e-8 wide and 0.02 long) the rounded normal tilts by ε over the sine of
    /// its angle, and the origin 3.5e-14 beyond such a face was called inside even in long double (a separated pair
    /// answered intersecting; an exact plane proves it apart, test_gjk_exact_plane_cgal.cpp). There the face counts as
    /// outside and the search goes on from it, as for a flat tetrahedron. On a well-shaped face the sign is kept: its
    /// error is below the tolerance, and the origin on a face of a tetrahedron deep inside D (coincident, nested
    /// shapes) stays "intersecting".
    static bool origin_side_certain(S side_o, const Vec3<S>& n, const Vec3<S>& e1, const Vec3<S>& e2,
                                    const Vec3<S>& p, S scale) noexcept {
        const S eps = std::numeric_limits<S>::epsilon();
        const S bound = S(16) * eps * (norm1(e1) * norm1(e2) * norm1(p));
        if (std::abs(side_o) > bound) return true;
        const S tol = S(1024) * eps * scale;
        return bound * bound <= tol * tol * norm2(n);
    }

    static void tetrahedron(const GjkSimplex<S>& s, Sel& r) noexcept {
        static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
        const S eps = std::numeric_limits<S>::epsilon();
        // A (numerically) flat tetrahedron cannot prove the origin inside: face normals built from nearly
        // coincident points are noise. Rounding in the coordinates is relative to their magnitude, so the
        // test compares the volume with ε·scale³ (treating a thin-but-real tetrahedron as flat is safe: it
        // only sends the search to the faces). The origin's side of each face is decided only beyond its own
        // rounding (`origin_side_certain`).
        S scale = S(0);
        for (std::size_t i = 0; i < 4; ++i) scale = std::max(scale, s.v[i].w.cwiseAbs().maxCoeff());
        const S vol6 = (s.v[1].w - s.v[0].w).dot((s.v[2].w - s.v[0].w).cross(s.v[3].w - s.v[0].w));
        const bool flat = !(std::abs(vol6) > S(256) * eps * scale * scale * scale);
        bool outside[4];
        bool any = false;
        for (int f = 0; f < 4; ++f) {
            const Vec3<S>& p = s.v[std::size_t(faces[f][0])].w;
            const Vec3<S> e1 = s.v[std::size_t(faces[f][1])].w - p, e2 = s.v[std::size_t(faces[f][2])].w - p;
            const Vec3<S> n = e1.cross(e2);
            const S side_l = n.dot(s.v[std::size_t(faces[f][3])].w - p);
            const S side_o = -n.dot(p);
            outside[f] = flat || !(side_o * side_l > S(0)) || !origin_side_certain(side_o, n, e1, e2, p, scale);
            any = any || outside[f];
        }
        if (!any) {
            r.inside = true;
            r.size = 4;
            r.v.setZero();
            return;
        }
        S best_d = std::numeric_limits<S>::infinity();
        bool found = false;
        Sel t;
        for (int f = 0; f < 4; ++f) {
            if (!outside[f]) continue;
            triangle(s, faces[f][0], faces[f][1], faces[f][2], t);
            const S d = t.v.squaredNorm();
            if (d < best_d || !found) { best_d = d; r = t; found = true; }
        }
    }

    /// The tetrahedron step of the cold boolean query, where vertex 3 is the newest support point. The same
    /// decisions as `tetrahedron` from fewer products: the edges from the new vertex give the three faces through
    /// it and the volume; the volume is the side of the opposite vertex for those three faces (n·(o − p) is 6 V
    /// for every face, up to orientation), so only the origin's side is evaluated per face. The flatness guard
    /// and the four origin-side tests are kept: "inside" is the overlap certificate. Only the boolean uses it, so
    /// the distance query's arithmetic is unchanged.
    static void tetrahedron_newest_last(const GjkSimplex<S>& s, Sel& r) noexcept {
        const S eps = std::numeric_limits<S>::epsilon();
        const Vec3<S>& p0 = s.v[0].w;
        const Vec3<S>& p1 = s.v[1].w;
        const Vec3<S>& p2 = s.v[2].w;
        const Vec3<S>& p3 = s.v[3].w;
        S scale = S(0);
        for (int k = 0; k < 3; ++k)
            scale = std::max({scale, std::abs(p0[k]), std::abs(p1[k]), std::abs(p2[k]), std::abs(p3[k])});
        const Vec3<S> e0 = minus(p0, p3), e1 = minus(p1, p3), e2 = minus(p2, p3);
        const Vec3<S> n01 = cross3(e0, e1), n12 = cross3(e1, e2), n20 = cross3(e2, e0);
        const S vol6 = dot3(e0, n12);  // = e1·n20 = e2·n01: the side of the opposite vertex, faces through p3
        const bool flat = !(std::abs(vol6) > S(256) * eps * scale * scale * scale);
        // Origin side of each face through p3: n·(0 − p3); outside when it differs in sign from the volume or
        // is within its rounding (`origin_side_certain`).
        auto out = [&](const Vec3<S>& n, S side_l, const Vec3<S>& ea, const Vec3<S>& eb, const Vec3<S>& p) {
            const S side_o = -dot3(n, p);
            return flat || !(side_o * side_l > S(0)) || !origin_side_certain(side_o, n, ea, eb, p, scale);
        };
        const bool out01 = out(n01, vol6, e0, e1, p3);  // face 3-0-1, opposite p2
        const bool out12 = out(n12, vol6, e1, e2, p3);  // face 3-1-2, opposite p0
        const bool out20 = out(n20, vol6, e2, e0, p3);  // face 3-2-0, opposite p1
        // The old face 0-1-2: the origin is on p3's side in exact arithmetic (p3 was found along −v), but the
        // certificate needs the test.
        const Vec3<S> f1 = minus(p1, p0), f2 = minus(p2, p0);
        const Vec3<S> m = cross3(f1, f2);
        const bool out012 = out(m, dot3(m, minus(p3, p0)), f1, f2, p0);
        if (!(out01 || out12 || out20 || out012)) {
            r.inside = true;
            r.size = 4;
            r.v.setZero();
            return;
        }
        S best_d = std::numeric_limits<S>::infinity();
        bool found = false;
        Sel t;
        auto consider = [&](bool out, int i0, int i1, int i2) {
            if (!out) return;
            triangle(s, i0, i1, i2, t);
            const S d = norm2(t.v);
            if (d < best_d || !found) { best_d = d; r = t; found = true; }
        };
        consider(out01, 0, 3, 1);
        consider(out20, 0, 2, 3);
        consider(out12, 1, 3, 2);
        consider(out012, 0, 1, 2);
    }

    /// True when the origin lies strictly inside conv(T ∪ {wp, wm}), T the triangle t0, t1, t2, with every sign
    /// beyond its rounding (`origin_side_certain`): wp and wm on opposite sides of T's plane, and the origin on
    /// the inner side of the six faces (edge of T, apex). The origin's side of T's own plane is not needed: on
    /// wp's side the three faces through wp and T's plane bound the tetrahedron (T, wp), on the other side
    /// those through wm bound (T, wm). This decides an origin that lies within rounding of a sliver T — GJK's
    /// "touching" for nested needles, whose Minkowski difference is 1e-8 thick around a plane the origin is on.
    static bool origin_in_bipyramid(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const Vec3<S>& wp,
                                    const Vec3<S>& wm) noexcept {
        const Vec3<S>* t[3] = {&t0, &t1, &t2};
        S scale = S(0);
        for (const Vec3<S>* q : {t[0], t[1], t[2], &wp, &wm})
            for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs((*q)[k]));
        // The apexes' sides of T's plane: the origin test in coordinates shifted by the apex.
        const Vec3<S>& p = *t[0];
        const Vec3<S> e1 = minus(*t[1], p), e2 = minus(*t[2], p);
        const Vec3<S> n = cross3(e1, e2);
        const S sp = dot3(n, minus(wp, p)), sm = dot3(n, minus(wm, p));
        if (!(sp * sm < S(0)) || !origin_side_certain(sp, n, e1, e2, minus(p, wp), scale) ||
            !origin_side_certain(sm, n, e1, e2, minus(p, wm), scale))
            return false;
        for (const Vec3<S>* apex : {&wp, &wm})
            for (int i = 0; i < 3; ++i) {
                const Vec3<S>& pi = *t[i];
                const Vec3<S> f1 = minus(*t[(i + 1) % 3], pi), f2 = minus(*apex, pi);
                const Vec3<S> nf = cross3(f1, f2);
                const S side_l = dot3(nf, minus(*t[(i + 2) % 3], pi));
                const S side_o = -dot3(nf, pi);
                if (!(side_o * side_l > S(0)) || !origin_side_certain(side_o, nf, f1, f2, pi, scale)) return false;
            }
        return true;
    }

    /// Witness-point weights of a final triangle simplex `s` (size 3) whose closest point is `v`, recomputed where
    /// the triangle is a sliver (smallest angle below 30°). Ericson's weights are ratios of products taken at
    /// one vertex, whose cancellation on a needle (two support points ~1e-8 apart, the third ~0.2 away) slid
    /// the witness points along it — by up to 3.7e-3 (the needle ~0.2 long) with the far vertex first, 1e-11
    /// otherwise — while |v| was right. Here, with the short edge u–w taken from the points (exact for a needle), the
    /// normal n built at the largest angle (`stable_normal`) and f the vertex opposite the short edge: f's
    /// weight is the area of (v, u, w) over the triangle's, n·((w − u) × (v − u)) / |n|², and the rest is
    /// split by where the line from f through v meets u–w. Done once per query, on the final simplex, so the
    /// iterations (and every distance) keep their bits.
    static void sliver_weights(GjkSimplex<S>& s, const Vec3<S>& v) noexcept {
        if (s.size != 3) return;
        const Vec3<S>& a = s.v[0].w;
        const Vec3<S>& b = s.v[1].w;
        const Vec3<S>& c = s.v[2].w;
        const Vec3<S> ab = b - a, ac = c - a;
        const S ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm(), bc2 = (c - b).squaredNorm();
        const Vec3<S> n0 = ab.cross(ac);
        if (!(n0.squaredNorm() < S(0.25) * std::max({ab2 * ac2, ab2 * bc2, ac2 * bc2}))) return;
        S edges2 = S(0);
        const Vec3<S> n = stable_normal(b, c, ab, ac, ab2, ac2, bc2, edges2);
        const S nn = n.squaredNorm();
        if (!(nn > S(0))) return;
        const Vec3<S>* pts[3] = {&a, &b, &c};
        const int f = bc2 <= ab2 && bc2 <= ac2 ? 0 : (ac2 <= ab2 ? 1 : 2);  // opposite the shortest edge
        const Vec3<S>& pf = *pts[f];
        const Vec3<S>& pu = *pts[(f + 1) % 3];
        const Vec3<S>& pw = *pts[(f + 2) % 3];
        const Vec3<S> uw = pw - pu;
        const S lf = n.dot(uw.cross(Vec3<S>(v - pu))) / nn;
        const S uw2 = uw.squaredNorm();
        if (!(lf >= S(0) && lf < S(1) && uw2 > S(0))) return;
        const Vec3<S> q = pf + (v - pf) / (S(1) - lf);  // on the line u–w
        const S t = std::clamp(S((q - pu).dot(uw) / uw2), S(0), S(1));
        S lam[3];
        lam[f] = lf;
        lam[(f + 1) % 3] = (S(1) - lf) * (S(1) - t);
        lam[(f + 2) % 3] = (S(1) - lf) * t;
        if (!(std::isfinite(lam[0]) && std::isfinite(lam[1]) && std::isfinite(lam[2]))) return;
        for (std::size_t k = 0; k < 3; ++k) s.lambda[k] = lam[k];
    }

    /// Closest point of the whole simplex `s` (size 1..4).
    static void select(const GjkSimplex<S>& s, Sel& r) noexcept {
        r.inside = false;
        switch (s.size) {
            case 1: point(s, 0, r); return;
            case 2: segment(s, 0, 1, r); return;
            case 3: triangle(s, 0, 1, 2, r); return;
            default: tetrahedron(s, r); return;
        }
    }

    /// Reduces `s` to the selection (indices ascending, so moving down in place is safe).
    static void apply(GjkSimplex<S>& s, const Sel& r) noexcept {
        if (r.inside) return;
        for (int k = 0; k < r.size; ++k) {
            const std::size_t from = std::size_t(r.idx[std::size_t(k)]);
            if (from != std::size_t(k)) s.v[std::size_t(k)] = s.v[from];
            s.lambda[std::size_t(k)] = r.lambda[std::size_t(k)];
        }
        s.size = r.size;
    }

    /// Reduces `s` to the sub-simplex holding its closest point `v`; true when the origin is inside a
    /// full-dimensional tetrahedron (then `v` is zero and `s` is unchanged).
    static bool solve(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        Sel r;
        select(s, r);
        apply(s, r);
        v = r.v;
        return r.inside;
    }
};

/// Support of D = A − B on the cores (or full shapes when `use_cores` is false), in A's frame;
/// `rel` maps B's frame into A's. `hints` (optional): start vertices {A, B} for `HintedSupport` shapes.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE void minkowski_support_into(GjkVertex<typename A::Scalar>& x, const A& a, const B& b,
                                                const Transform<typename A::Scalar>& rel,
                                                const Vec3<typename A::Scalar>& d,
                                                std::uint32_t* hints = nullptr) noexcept {
    using S = typename A::Scalar;
    const Vec3<S> db = rotate_back(rel.R, neg(d));
    if constexpr (use_cores) {
        x.a = core_support_hinted(a, d, hints);
        x.b_local = core_support_hinted(b, db, hints ? hints + 1 : nullptr);
    } else {
        x.a = a.support(d);
        x.b_local = b.support(db);
    }
    x.b = place(rel, x.b_local);
    x.w = minus(x.a, x.b);
    x.d = d;
}
/// The same, returned by value.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE GjkVertex<typename A::Scalar> minkowski_support(const A& a, const B& b,
                                                                    const Transform<typename A::Scalar>& rel,
                                                                    const Vec3<typename A::Scalar>& d,
                                                                    std::uint32_t* hints = nullptr) noexcept {
    GjkVertex<typename A::Scalar> x;
    minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
    return x;
}

/// True when the rounding of the triangle step `sel` (closest point v on triangle s.v[sel.idx[0..2]]) may
/// exceed `tol`: the computed normal tilts by about ε over the sine of the angle it is built at (the largest,
/// see `SimplexSolver::stable_normal`), which moves the projection by that angle times the lever arm, the
/// farthest vertex from v. Compared in squares, without division.
template <class S> [[nodiscard]] inline bool triangle_step_unreliable(const GjkSimplex<S>& s,
                                                                      const SimplexSelection<S>& sel, S tol) noexcept {
    if (!(sel.normal2 > S(0))) return true;
    S lever2 = S(0);
    for (int k = 0; k < 3; ++k)
        lever2 = std::max(lever2, (s.v[std::size_t(sel.idx[std::size_t(k)])].w - sel.v).squaredNorm());
    const S eps = std::numeric_limits<S>::epsilon();
    return eps * eps * sel.edges2 * lever2 > tol * tol * sel.normal2;
}

/// True when the triangle step on s.v[0..2] may move its closest point by `tol` (tol2 = tol²) or more through
/// rounding. The edges carry the coordinates' absolute rounding, ε·M (M the largest |w|), which on a short edge
/// tilts the normal by ε·M·P/|n| (P the perimeter, |n| twice the area) and moves the projection by that times a
/// lever arm ≤ P; a factor 4 covers the step's own operations. triangle_step_unreliable measures the rounding
/// relative to the edges' lengths, which misses it where a short edge sits far from the origin. Compared in
/// squares (P² ≤ 3·Σ|e|²), no root.
template <class S> [[nodiscard]] inline bool sliver_step_may_reach(const GjkSimplex<S>& s, S tol2) noexcept {
    const Vec3<S>& a = s.v[0].w;
    const Vec3<S>& b = s.v[1].w;
    const Vec3<S>& c = s.v[2].w;
    const S m2 = std::max({a.squaredNorm(), b.squaredNorm(), c.squaredNorm()});
    const S p2 = S(3) * ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm());
    const S nn = (b - a).cross(c - a).squaredNorm();
    const S eps = std::numeric_limits<S>::epsilon();
    return S(16) * eps * eps * m2 * p2 * p2 > tol2 * nn;
}

/// The sub-simplex step on the first `n + 1` vertices of `s`, in `wider_t<S>`. With `always` false: true
/// (and `sel` set) when that step's closest point is strictly nearer than the one of the first `n` vertices,
/// both in the wide type. With `always` true: `sel` is the step's selection whenever it is not "inside".
template <class S> inline bool refine_step(const GjkSimplex<S>& s, int n, SimplexSelection<S>& sel,
                                           bool always = false) noexcept {
    using W = wider_t<S>;
    GjkSimplex<W> ws;
    for (int i = 0; i <= n; ++i) ws.v[std::size_t(i)].w = s.v[std::size_t(i)].w.template cast<W>();
    SimplexSelection<W> full, prev;
    ws.size = n + 1;
    SimplexSolver<W>::select(ws, full);
    if (full.inside || !full.v.allFinite()) return false;
    if (!always) {
        ws.size = n;
        SimplexSolver<W>::select(ws, prev);
        if (!(full.v.squaredNorm() < prev.v.squaredNorm())) return false;
    }
    sel.inside = false;
    sel.size = full.size;
    for (int k = 0; k < full.size; ++k) {
        sel.idx[std::size_t(k)] = full.idx[std::size_t(k)];
        sel.lambda[std::size_t(k)] = S(full.lambda[std::size_t(k)]);
    }
    sel.v = full.v.template cast<S>();
    return true;
}

/// The tolerance term of the gap test below: ε_rel·|v|², or ε_rel·|v|·(|v| − margin) beyond a margin.
template <class S> [[nodiscard]] inline S gap_tolerance(S vv, S margin, S rel_tolerance) noexcept {
    if (margin > S(0)) {
        const S core = std::sqrt(vv);
        if (core > margin) return rel_tolerance * core * (core - margin);
    }
    return rel_tolerance * vv;
}

/// GJK's convergence test on |v| (v the point of the simplex nearest the origin, w the support point along
/// −v, vw = v·w, vv = |v|², size2 = the squared size of D's support points): the gap |v| − v·w/|v| between
/// the upper and lower bound is within ε_rel·|v|² + 16·ε·|v|·size, compared in squares (no sqrt per
/// iteration). With margins (capsules, spheres, Inflated: GJK runs on the cores) the caller gets
/// |v| − margin, so the relative term is ε_rel·|v|·(|v| − margin): ε_rel·|v|² would be
/// ε_rel·(1 + margin/distance) relative on the result (2e-8 on close capsule pairs). Within the margin
/// (overlap) only the decision matters and ε_rel·|v|² stays.
template <class S>
[[nodiscard]] inline bool gap_converged(S vv, S vw, S margin, S size2, S rel_tolerance) noexcept {
    constexpr S eps = std::numeric_limits<S>::epsilon();
    const S excess = vv - vw - gap_tolerance(vv, margin, rel_tolerance);
    return excess <= S(0) || excess * excess <= S(256) * eps * eps * vv * size2;
}

/// True when a loop's closest point v (vv = |v|²) lies beyond margin + tf·max(size, margin), gjk_finish's
/// touching tolerance: an exit there would be reported as "separated".
template <class S> [[nodiscard]] inline bool separation_claimed(S vv, S margin, S tf, S size2) noexcept {
    const S thr = margin + tf * std::max(std::sqrt(size2), margin);
    return vv > thr * thr;
}

/// Certification of a "separated" outcome that no supporting plane backs. A separated answer claims a plane
/// between the shapes; its proof is a lower bound on the distance, v·w/|v| for a direction v and the support
/// point w of D along −v (van den Bergen 1999, §3: the plane through w orthogonal to v supports D), above the
/// touching tolerance. GJK's other exits — the gap test, a repeated support point, a step without progress —
/// stop on |v|, an upper bound only while the sub-simplex steps are exact: near contact on curved shapes the
/// support points cluster into needle triangles and flat tetrahedra, the double step misplaces v and GJK
/// stopped with |v| above the tolerance on pairs that overlap by 1e-12 … 1e-9 of their size (24 of 3,600 such
/// pairs in a driver: cones, cylinders, ellipsoids). For those rare exits this continues from the final simplex
/// with the sub-simplex steps in `wider_t<S>` (the support points stay exact points of D, now combined with
/// a 2048× finer rounding) until a plane proves separation (`separated`, `lower` > margin + tolerance), four
/// points enclose the origin (`intersecting`), or |v| reaches the tolerance; when it stops without deciding,
/// the answer is `touching`: conservative for collision detection, and no plane was found above the
/// tolerance. `s` holds a, b, w of its first s.size vertices (A's frame); `v`, `s`, `size2`, `lower`, `sep`
/// and `iterations` are updated.
template <bool use_cores, SupportMapped A, SupportMapped B>
inline GjkStatus certify_separation(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                                    const GjkSettings<typename A::Scalar>& settings, typename A::Scalar margin,
                                    GjkSimplex<typename A::Scalar>& s, Vec3<typename A::Scalar>& v,
                                    typename A::Scalar& size2, typename A::Scalar& lower,
                                    GjkVertex<typename A::Scalar>& sep, std::uint32_t* hints,
                                    int& iterations) noexcept {
    using S = typename A::Scalar;
    using W = wider_t<S>;
    const S tf = settings.touch_factor * std::numeric_limits<S>::epsilon();
    GjkSimplex<W> ws;
    auto widen = [](const GjkVertex<S>& x) { return Vec3<W>(x.a.template cast<W>() - x.b.template cast<W>()); };
    ws.size = s.size;
    for (int i = 0; i < s.size; ++i) ws.v[std::size_t(i)].w = widen(s.v[std::size_t(i)]);
    SimplexSelection<W> sel;
    // Moves both simplices to the selection (indices ascending: moving down in place is safe).
    auto apply = [&]() {
        for (int k = 0; k < sel.size; ++k) {
            const std::size_t from = std::size_t(sel.idx[std::size_t(k)]);
            if (from != std::size_t(k)) { s.v[std::size_t(k)] = s.v[from]; ws.v[std::size_t(k)].w = ws.v[from].w; }
            s.lambda[std::size_t(k)] = S(sel.lambda[std::size_t(k)]);
        }
        s.size = ws.size = sel.size;
    };
    Vec3<W> vw = v.template cast<W>();
    if (ws.size > 0) {
        SimplexSolver<W>::select(ws, sel);
        if (sel.inside) { v.setZero(); return GjkStatus::intersecting; }
        if (!all_finite(sel.v)) return GjkStatus::touching;
        apply();
        vw = sel.v;
    }
    for (int k = 0; k < settings.max_iterations; ++k) {
        const W thr = W(margin) + W(tf) * W(std::max(std::sqrt(size2), margin));
        const W vv = vw.squaredNorm();
        if (!(vv > thr * thr)) break;  // |v| within the tolerance: no separation left to prove
        const Vec3<S> d = (-vw).template cast<S>();
        ++iterations;
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
        if (!all_finite(x.w)) { v = vw.template cast<S>(); return GjkStatus::degenerate; }
        size2 = std::max(size2, norm2(x.w));
        // The bound along the direction actually queried (−d, exact in W), from the exact points of D.
        const Vec3<W> u = (-d).template cast<W>();
        const Vec3<W> wx = widen(x);
        const W lb = u.dot(wx) / u.norm();
        lower = std::max(lower, S(lb));
        if (lb > thr) {
            sep = x;
            v = -d;
            return GjkStatus::separated;
        }
        bool duplicate = false;
        for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.v[std::size_t(i)].w == x.w;
        if (duplicate) break;
        ws.v[std::size_t(ws.size++)].w = wx;
        ++s.size;
        SimplexSolver<W>::select(ws, sel);
        if (sel.inside) { v.setZero(); return GjkStatus::intersecting; }
        if (!(sel.v.squaredNorm() < vv)) { --s.size; --ws.size; break; }  // the wide rounding floor
        apply();
        vw = sel.v;
    }
    v = vw.template cast<S>();
    return GjkStatus::touching;
}

/// What `certify_exit` found (see certify_separation).
template <class S> struct CertifiedExit {
    GjkStatus status;
    Vec3<S> v;
    S size2, lower;
    GjkVertex<S> sep;
    int iterations;
};

/// certify_separation for gjk_loop's exits, out of line and on copies (v, size², bound, hints, relative pose), so
/// that the loop's own state never has its address taken on the common path (taking it cost the cold boolean's
/// box cells 8–13 %: values reloaded after stores through the simplex).
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH CertifiedExit<typename A::Scalar> certify_exit(const A& a, const B& b,
                                                                Transform<typename A::Scalar> rel,
                                                                const GjkSettings<typename A::Scalar>& settings,
                                                                typename A::Scalar margin,
                                                                GjkSimplex<typename A::Scalar>& s,
                                                                Vec3<typename A::Scalar> v, typename A::Scalar size2,
                                                                typename A::Scalar lower, std::uint32_t hint_a,
                                                                std::uint32_t hint_b) noexcept {
    using S = typename A::Scalar;
    CertifiedExit<S> c;
    std::uint32_t hints[2] = {hint_a, hint_b};
    c.sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    c.iterations = 0;
    c.status = certify_separation<use_cores>(a, b, rel, settings, margin, s, v, size2, lower, c.sep, hints,
                                             c.iterations);
    c.v = v;
    c.size2 = size2;
    c.lower = lower;
    return c;
}

/// GJK's touching exit (|v| within the touching tolerance of zero, no margins): the origin may lie deep inside D
/// with the final simplex through it — nested needles, whose Minkowski difference is 1e-8 thick around the plane or
/// the axis the origin is on (the hard-case count's nested and near-contact needle pairs ended "touching", in long
/// double too). A bipyramid of points of D around the origin proves the overlap
/// (`SimplexSolver::origin_in_bipyramid`): on a triangle, D's support points along ±n (n its normal) as apexes;
/// on a segment p–q — or a triangle whose edge nearest the origin carries it — p and q as apexes over the triangle
/// of D's support points along three directions 120° apart around the segment. Out of line: rare.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH bool touching_simplex_proves_overlap(const A& a, const B& b, Transform<typename A::Scalar> rel,
                                                     const GjkSimplex<typename A::Scalar>& s) noexcept {
    using S = typename A::Scalar;
    auto support = [&](const Vec3<S>& d) { return minkowski_support<use_cores>(a, b, rel, d).w; };
    // Decided in the wider type (the points are exact there): across a needle 1e-8 thick and 0.1 long the side
    // products' rounding in double (ε times the cube of the length) exceeds them where thickness/length < 6e-8.
    using W = wider_t<S>;
    auto in_bipyramid = [](const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const Vec3<S>& wp,
                           const Vec3<S>& wm) {
        return SimplexSolver<W>::origin_in_bipyramid(t0.template cast<W>(), t1.template cast<W>(),
                                                     t2.template cast<W>(), wp.template cast<W>(),
                                                     wm.template cast<W>());
    };
    // Around segment p–q: three support points whose triangle the segment pierces.
    auto around_segment = [&](const Vec3<S>& p, const Vec3<S>& q) {
        const Vec3<S> axis = minus(q, p);
        int k = 0;  // the coordinate axis least aligned with the segment
        for (int i = 1; i < 3; ++i) k = std::abs(axis[i]) < std::abs(axis[k]) ? i : k;
        const Vec3<S> u = cross3(axis, Vec3<S>(Vec3<S>::Unit(k)));
        const Vec3<S> w = cross3(axis, u);
        const S nu = std::sqrt(norm2(u)), nw = std::sqrt(norm2(w));
        if (!(nu > S(0) && nw > S(0)) || !all_finite(u) || !all_finite(w)) return false;
        const S c = S(-0.5), sn = S(0.86602540378443864676);  // cos, sin 120°
        const Vec3<S> uu = u / nu, ww = w / nw;
        const Vec3<S> e0 = support(uu);
        const Vec3<S> e1 = support(Vec3<S>(c * uu + sn * ww)), e2 = support(Vec3<S>(c * uu - sn * ww));
        if (!all_finite(e0) || !all_finite(e1) || !all_finite(e2)) return false;
        return in_bipyramid(e0, e1, e2, p, q);
    };
    if (s.size == 2) return around_segment(s.v[0].w, s.v[1].w);
    if (s.size != 3) return false;
    const Vec3<S>& p0 = s.v[0].w;
    const Vec3<S> ab = minus(s.v[1].w, p0), ac = minus(s.v[2].w, p0);
    const S ab2 = norm2(ab), ac2 = norm2(ac), bc2 = norm2(minus(s.v[2].w, s.v[1].w));
    S edges2 = S(0);
    const Vec3<S> n = SimplexSolver<S>::stable_normal(s.v[1].w, s.v[2].w, ab, ac, ab2, ac2, bc2, edges2);
    if (norm2(n) > S(0) && all_finite(n)) {
        const Vec3<S> wp = support(n), wm = support(neg(n));
        if (all_finite(wp) && all_finite(wm) && in_bipyramid(s.v[0].w, s.v[1].w, s.v[2].w, wp, wm)) return true;
    }
    // The origin on (within rounding of) an edge: that edge as the segment.
    int best = 0;
    S best_d = std::numeric_limits<S>::infinity();
    for (int e = 0; e < 3; ++e) {
        typename SimplexSolver<S>::Sel sel;
        SimplexSolver<S>::segment(s, e, (e + 1) % 3, sel);
        const S d = norm2(sel.v);
        if (d < best_d) { best_d = d; best = e; }
    }
    return around_segment(s.v[std::size_t(best)].w, s.v[std::size_t((best + 1) % 3)].w);
}

/// A touching result (no margins) whose final simplex proves the overlap (`touching_simplex_proves_overlap`)
/// becomes intersecting, reported as every proven overlap is: distance 0, no witness points.
template <SupportMapped A, SupportMapped B>
inline void prove_touching_overlap(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                                   GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    if (r.status != GjkStatus::touching || margin_of(a) + margin_of(b) > S(0)) return;
    if (!touching_simplex_proves_overlap<true>(a, b, rel, r.simplex)) return;
    r.status = GjkStatus::intersecting;
    r.distance = S(0);
    r.point_a.setZero();
    r.point_b.setZero();
    r.normal.setZero();
}

/// The GJK loop on D in A's frame. `early_exit_margin` ≥ 0, the shapes' summed margins, enables the boolean
/// early exit (stop as soon as a plane proves the core distance exceeds it) and sets the distance tolerance
/// relative to the distance the caller gets (core distance − margin). Returns the status on the cores; `v` is the
/// final closest point, `size_out` the larger of |t_rel| and the largest |w| seen (the scale for the touching
/// tolerance), `lower_out` the best
/// separating-plane bound the boolean test found (0 for distance queries, which do not need it). `boolean` (a
/// template parameter, so that each query's loop carries none of the other's bookkeeping: 3.6 % fewer instructions
/// per warm distance query in the coherent benchmark) selects the early exit.
///
/// The boolean exit tests every support point, the very first one included: for any direction u, w = s_D(−u)
/// minimises u·x over D, so u·w/|u| > 0 is a separating plane whether or not u is the closest point of the
/// current simplex (distant pairs are then decided by one support pair). A coherent pair's cached direction, the
/// one that separated it the frame before, is tested before the loop (`warm_direction_separates`).
template <bool use_cores, bool boolean, SupportMapped A, SupportMapped B>
inline GjkStatus gjk_loop(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                          const GjkSettings<typename A::Scalar>& settings, GjkCache<typename A::Scalar>* cache,
                          typename A::Scalar early_exit_margin, GjkSimplex<typename A::Scalar>& s,
                          Vec3<typename A::Scalar>& v, typename A::Scalar& size_out, int& iterations,
                          typename A::Scalar& lower_out, typename A::Scalar exit_quality = 0,
                          GjkVertex<typename A::Scalar>* exit_support = nullptr,
                          bool* tolerance_met = nullptr) noexcept {
    using S = typename A::Scalar;
    using Solver = SimplexSolver<S>;
    const S eps = std::numeric_limits<S>::epsilon();
    // The start direction from the centres; a warm start replaces it with its rebuilt simplex's closest point
    // (for the shapes the cache's points belong to the rebuild usually succeeds; centre_direction if not).
    const bool rebuilds = cache && cache->size > 0 && cache->shape_a == static_cast<const void*>(&a) &&
                          cache->shape_b == static_cast<const void*>(&b);
    auto centre_direction = [&] {
        v = Vec3<S>(Vec3<S>(a.center()) - place(rel, Vec3<S>(b.center())));
        if (!(v.squaredNorm() > S(0)) || !v.allFinite()) v = Vec3<S>::UnitX();
    };
    if (rebuilds) v = Vec3<S>::UnitX();
    else centre_direction();
    s.size = 0;
    // Locals, written out on return: as reference parameters they were reloaded after every store through
    // the simplex (possible aliasing), putting a sqrt/division latency on each iteration's critical path.
    // size2: the largest |w|² seen (tolerances scale with its root, taken only where needed: a sqrt per
    // iteration on the path to the next support query showed in the profile).
    S size2 = S(0), lower_bound = S(0);
    // The touching tolerance (256ε·size) scales with |t_rel| too, the magnitude whose rounding B's points carry in
    // A's frame: |w| alone vanishes on a touching pair, and a warm start has only support points near the contact
    // (the seeded hard-case count found warm booleans and distances answering "separated" at 1e-16 of the size
    // where long double proves the overlap). The convergence test keeps the largest |w| (size2).
    const S mag2 = rel.t.squaredNorm();
    auto tol2 = [&] { return std::max(size2, mag2); };
    // A boolean query waiting for a better plane (exit_quality) keeps the best one's direction and support point:
    // it is the answer if the query ends before (best_saved; otherwise the exit's own direction is the best).
    Vec3<S> best_u = v;
    GjkVertex<S> best_x;
    // Read only when best_saved; zeroed in the boolean loop all the same, where GCC cannot see that through the
    // inlined exits (-Wmaybe-uninitialized).
    if constexpr (boolean) best_x.w = best_x.a = best_x.b = best_x.d = best_x.b_local = Vec3<S>::Zero();
    bool best_saved = false;
    // v·w and |v|² at the loop's exits on |v| (gap test, repeated point, no progress): the plane bound there.
    S exit_vw = S(0), exit_vv = S(0);
    // Whether a separated exit's gap |v|² − v·w, the bracket on the distance, is within 4× the tolerance:
    // false where the loop stopped on the rounding floor (the gap test's second term), a repeated point or a
    // step without progress with a wider bracket. gjk_query refines those in long double. (Brackets of 1–1.6×
    // the tolerance are common on close polytope pairs, ~2 % of the coherent near-touching frames; refining
    // them would cost microseconds for nothing the 1e-9 target needs.)
    bool met = true;
    // Hill-climbing starts for polyhedra: each support query starts at the previous one's vertex (under
    // coherence last frame's, from the cache), instead of the hull's fixed seeds.
    std::uint32_t hints[2] = {cache ? cache->hint_a : std::uint32_t(-1), cache ? cache->hint_b : std::uint32_t(-1)};
    auto done = [&](GjkStatus st) CDKIT_LAMBDA_INLINE {
        size_out = std::sqrt(tol2());
        // A separated boolean reports the plane of its best bound (the exit's own direction may be weaker
        // when a warm start waited for exit_quality).
        if (boolean && st == GjkStatus::separated && best_saved && exit_support) {
            v = best_u;
            *exit_support = best_x;
        }
        lower_out = lower_bound;
        if (cache) { cache->hint_a = hints[0]; cache->hint_b = hints[1]; }
        if (tolerance_met) *tolerance_met = met;
        return st;
    };
    iterations = 0;
    S vv = std::numeric_limits<S>::infinity();
    GjkStatus status = GjkStatus::max_iterations;
    // Boolean exit on the support point x found along −u: true when the plane proves separation.
    // With `exit_quality` κ > 0 (warm-started queries) a plane is only accepted once its gap is at least κ
    // times the upper bound |v| − margin, so the direction cached for the next frame keeps a margin under
    // coherent motion instead of barely separating (the cached direction's own test, warm_direction_separates
    // before the loop, is exempt).
    auto separates = [&](const Vec3<S>& u, const GjkVertex<S>& x) {
        const S uw = u.dot(x.w);
        // No positive plane now and none before: nothing to test (skips the sqrt and division on the
        // iterations that do not separate).
        if (!(uw > S(0)) && !(lower_bound > S(0))) return false;
        const S un = u.norm();
        if (!(un > S(0))) return false;
        const S bound = uw / un;
        const bool improved = bound > lower_bound;
        if (improved) lower_bound = bound;
        // Same threshold as gjk_query applies to the early exit.
        const S size = std::sqrt(tol2());
        if (!(boolean &&
              lower_bound > early_exit_margin + settings.touch_factor * eps * std::max(size, early_exit_margin)))
            return false;
        if (exit_quality > S(0) &&
            !(s.size > 0 && lower_bound - early_exit_margin >= exit_quality * (un - early_exit_margin))) {
            if (improved) {
                best_u = u;
                best_x = x;
                best_saved = true;
            }
            return false;
        }
        if (improved) best_saved = false;
        return true;
    };
    auto store = [&](const GjkVertex<S>* first) {
        if (!cache) return;
        int k = 0;
        auto put = [&](const GjkVertex<S>& x) {
            cache->directions[std::size_t(k)] = x.d;
            cache->point_a[std::size_t(k)] = x.a;
            cache->point_b[std::size_t(k)] = x.b_local;
            ++k;
        };
        if (first) put(*first);
        for (int i = 0; i < s.size && k < 4; ++i) put(s.v[std::size_t(i)]);
        cache->size = k;
        cache->shape_a = &a;
        cache->shape_b = &b;
    };
    auto note_exit = [&](const GjkVertex<S>& x) {
        exit_vw = v.dot(x.w);
        exit_vv = vv;
    };
    typename Solver::Sel sel;
    if (cache && cache->size > 0) {
        const int n = std::min(cache->size, 4);
        for (int i = 0; i < n; ++i) {
            // Built in the simplex's free slot (s.size < 4 here), which it joins by ++s.size.
            GjkVertex<S>& x = s.v[std::size_t(s.size)];
            if (rebuilds) {
                // The stored support points under the new poses: points of D, no support query.
                x.a = cache->point_a[std::size_t(i)];
                x.b_local = cache->point_b[std::size_t(i)];
                x.b = place(rel, x.b_local);
                x.w = x.a - x.b;
                x.d = cache->directions[std::size_t(i)];
            } else {
                x = minkowski_support<use_cores>(a, b, rel, cache->directions[std::size_t(i)], hints);
            }
            if (!x.w.allFinite()) continue;
            size2 = std::max(size2, x.w.squaredNorm());
            bool dup = false;
            for (int j = 0; j < s.size; ++j) dup = dup || s.v[std::size_t(j)].w == x.w;
            if (!dup) ++s.size;
        }
        if (s.size > 0) {
            Solver::select(s, sel);
            if (sel.inside) {
                // Four points of D around the origin: overlap, without a support query when reused.
                v.setZero();
                store(nullptr);
                return done(GjkStatus::intersecting);
            }
            Solver::apply(s, sel);
            v = sel.v;
            vv = v.squaredNorm();
            if (!(vv > S(0))) { s.size = 0; vv = std::numeric_limits<S>::infinity(); v = Vec3<S>::UnitX(); }
        } else if (rebuilds) {
            centre_direction();
        }
    }
    int refinements = 0;
    for (int it = 0; it < settings.max_iterations; ++it) {
        iterations = it + 1;
        const Vec3<S> d = -v;
        // Written straight into the simplex's free slot (s.size ≤ 3 here); it joins the simplex by ++s.size.
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
        if (!all_finite(x.w)) { status = GjkStatus::degenerate; break; }
        size2 = std::max(size2, x.w.squaredNorm());
        if (boolean && separates(v, x)) {
            status = GjkStatus::separated;
            if (exit_support) *exit_support = x;
            store(&x);
            return done(status);
        }
        if (s.size > 0) {
            // v·w/|v| is a lower bound on the distance (the plane through w orthogonal to v supports D; the
            // boolean test above already kept it). Converged: the gap between upper bound |v| and the lower
            // bound is within tolerance (the ε·|v|·size term is the rounding floor of v·w).
            if (gap_converged(vv, v.dot(x.w), early_exit_margin, size2, settings.rel_tolerance)) {
                note_exit(x);
                status = GjkStatus::separated;
                break;
            }
            bool duplicate = false;
            for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.v[std::size_t(i)].w == x.w;
            if (duplicate) {
                note_exit(x);
                // The support point is already in the simplex: in exact arithmetic v is optimal. When the
                // gap test failed, v may be off by the sub-simplex step's rounding (see below): recompute it
                // in the wider type and, if it moved, query again from there.
                if constexpr (!std::is_same_v<S, wider_t<S>>) {
                    if (refinements < 8 && s.size > 1) {
                        ++refinements;
                        if (refine_step(s, s.size - 1, sel, true) && sel.v != v) {
                            Solver::apply(s, sel);
                            v = sel.v;
                            vv = v.squaredNorm();
                            continue;
                        }
                    }
                }
                status = GjkStatus::separated;
                break;
            }
        }
        const int old_size = s.size++;
        Solver::select(s, sel);
        if constexpr (!std::is_same_v<S, wider_t<S>>) {
            // A distance query must not trust a triangle step whose normal rounding (ε over the sine of the
            // triangle's angle, times the lever arm) exceeds a tenth of the tolerance: on curved surfaces the
            // support points cluster into slivers, and the step then puts v *below* the simplex — |v| is no
            // longer an upper bound and the gap test passes short of the distance (issue 5: up to 7e-7
            // relative on close cones). Redo that step in the wider type (x87 long double for double).
            if (!boolean && !sel.inside && sel.size == 3 &&
                triangle_step_unreliable(s, sel, S(0.1) * settings.rel_tolerance * sel.v.norm()))
                refine_step(s, s.size - 1, sel, true);
        }
        if (sel.inside) { v.setZero(); status = GjkStatus::intersecting; break; }
        const S nvv = sel.v.squaredNorm();
        if (!(nvv == nvv)) { s.size = old_size; status = GjkStatus::degenerate; break; }
        const S tiny2 = settings.touch_factor * settings.touch_factor * eps * eps * tol2();  // (256·ε·size)²
        if (nvv <= tiny2) { Solver::apply(s, sel); v = sel.v; status = GjkStatus::touching; break; }
        if (old_size > 0 && !(nvv < vv)) {
            note_exit(x);
            // No progress. On curved shapes the support points cluster and the sub-simplex step loses
            // accuracy before the gap test is met (a sliver triangle's normal is rounding noise: issue 5 found
            // |v| up to 1e-7 relative *below* the distance). Redo this step and the previous simplex's in a
            // wider type: if the new point does make progress, continue; otherwise stop with the previous
            // simplex's accurate closest point. Rare (only at this exit), so the wider arithmetic is cheap.
            if constexpr (!std::is_same_v<S, wider_t<S>>) {
                if (refinements < 8) {
                    ++refinements;
                    if (refine_step(s, old_size, sel)) {
                        Solver::apply(s, sel);
                        v = sel.v;
                        vv = v.squaredNorm();
                        continue;
                    }
                    s.size = old_size;
                    if (refine_step(s, old_size - 1, sel, true)) { Solver::apply(s, sel); v = sel.v; }
                    status = GjkStatus::separated;
                    break;
                }
            }
            // Rounding floor reached; keep the better previous simplex (untouched by select).
            s.size = old_size;
            status = GjkStatus::separated;
            break;
        }
        Solver::apply(s, sel);
        v = sel.v;
        vv = nvv;
    }
    if (status == GjkStatus::separated) {
        // "Separated" claims a plane: v·w/|v| above the touching tolerance for some support point w (van den
        // Bergen 1999's lower bound; compared in squares, no sqrt without margins). An exit on |v| without one
        // (near contact, where the double sub-simplex step can misplace v) is decided by certify_exit.
        const S tf = settings.touch_factor * eps;
        S thr2 = tf * tf * tol2();
        if (early_exit_margin > S(0)) {
            const S thr = early_exit_margin + tf * std::max(std::sqrt(tol2()), early_exit_margin);
            thr2 = thr * thr;
        }
        const bool proven = (lower_bound > S(0) && lower_bound * lower_bound > thr2) ||
                            (exit_vw > S(0) && exit_vw * exit_vw > thr2 * exit_vv);
        if (tolerance_met)
            met = exit_vv - exit_vw <= S(4) * gap_tolerance(exit_vv, early_exit_margin, settings.rel_tolerance);
        if (!proven && v.squaredNorm() > thr2) {
            const CertifiedExit<S> c = certify_exit<use_cores>(a, b, rel, settings, early_exit_margin, s, v, size2,
                                                               lower_bound, hints[0], hints[1]);
            status = c.status;
            v = c.v;
            size2 = c.size2;
            lower_bound = c.lower;
            iterations += c.iterations;
            best_saved = false;
            if (status == GjkStatus::separated && exit_support) *exit_support = c.sep;
        }
    }
    store(nullptr);
    return done(status);
}

/// The result of a query from the loop's outcome: status, distance, normal and world-frame points.
template <SupportMapped A, SupportMapped B>
inline void gjk_finish(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                       const GjkSettings<typename A::Scalar>& settings, GjkResult<typename A::Scalar>& r,
                       GjkStatus st, const Vec3<typename A::Scalar>& v, typename A::Scalar size,
                       typename A::Scalar lower, const GjkVertex<typename A::Scalar>& sep, bool boolean) noexcept {
    using S = typename A::Scalar;
    const S margin = margin_of(a) + margin_of(b);
    const S tiny = settings.touch_factor * std::numeric_limits<S>::epsilon() * std::max(size, margin);
    if (boolean && st == GjkStatus::separated && lower > margin + tiny) {
        r.status = GjkStatus::separated;
        r.distance = lower - margin;
        const S vn = v.norm();
        if (vn > S(0)) {
            const Vec3<S> n = -v / vn;
            r.normal = rotate(pose_a.R, n);  // a separating direction, A towards B
            if (sep.w.allFinite()) {
                // The supporting points of that plane: A's extreme towards B and B's towards A.
                r.point_a = place(pose_a, pushed_out(a, sep.a, n));
                r.point_b = place(pose_a, pushed_out(b, sep.b, Vec3<S>(-n)));
            }
        }
        return;
    }
    if (st == GjkStatus::intersecting) {  // no witness points: the result reports none for an overlap
        r.status = GjkStatus::intersecting;
        r.distance = S(0);
        return;
    }
    // Witness points on the cores, then push them out by the margins along the normal.
    SimplexSolver<S>::sliver_weights(r.simplex, v);
    Vec3<S> pa = Vec3<S>::Zero(), pb = Vec3<S>::Zero();
    for (int i = 0; i < r.simplex.size; ++i) {
        pa += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].a;
        pb += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].b;
    }
    S core = v.norm();
    Vec3<S> n = core > S(0) ? Vec3<S>(-v / core) : Vec3<S>::Zero();  // from A towards B
    S dist = core - margin;
    r.point_a = place(pose_a, pushed_out(a, pa, n));
    r.point_b = place(pose_a, pushed_out(b, pb, Vec3<S>(-n)));
    r.normal = rotate(pose_a.R, n);
    if (st == GjkStatus::max_iterations || st == GjkStatus::degenerate) {
        r.status = st;
        r.distance = std::max(dist, S(0));
        return;
    }
    if (st == GjkStatus::touching || std::abs(dist) <= tiny) {
        r.status = margin > S(0) && dist < -tiny ? GjkStatus::intersecting : GjkStatus::touching;
        r.distance = S(0);
        return;
    }
    r.status = dist > S(0) ? GjkStatus::separated : GjkStatus::intersecting;
    r.distance = std::max(dist, S(0));
}

/// `certify_separation` and then `gjk_finish`, out of line: the arguments are copies and the relative pose is
/// formed again, so that the callers' loop state (v, size², the hints, their relative pose) never has its address
/// taken — passing `rel` by reference cost the cold boolean's box cells 8–13 % (it was reloaded after stores).
template <SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH void finish_certified(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                      const Transform<typename A::Scalar>& pose_b,
                                      const GjkSettings<typename A::Scalar>& settings,
                                      GjkResult<typename A::Scalar>& r, Vec3<typename A::Scalar> v,
                                      typename A::Scalar size2, typename A::Scalar lower, std::uint32_t hint_a,
                                      std::uint32_t hint_b, bool boolean) noexcept {
    using S = typename A::Scalar;
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    std::uint32_t hints[2] = {hint_a, hint_b};
    GjkVertex<S> sep;
    sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    const GjkStatus st = certify_separation<true>(a, b, rel, settings, margin_of(a) + margin_of(b), r.simplex, v,
                                                  size2, lower, sep, hints, r.iterations);
    gjk_finish(a, pose_a, b, settings, r, st, v, std::sqrt(size2), lower, sep, boolean);
}

/// The bounding-ball pre-test of the cold boolean query (`GjkSettings::bounding_ball_test`): true, with `r`
/// filled in, when the balls decide the pair. ca, cb: the computed world centres, delta = ca − cb, dd = |delta|²,
/// tf = touch_factor·ε. The slack tf·(|t_a|₁ + |t_b|₁ + |ca|₁ + |cb|₁ + R_a + R_b) exceeds the rounding of the
/// centres (a rotation and a translation, a few ε of those magnitudes), of delta and of the squares many
/// times over, and is at least the touching tolerance gjk_finish applies (256ε·max(|w|, margin) with
/// |w| ≤ |ca − cb| + R_a + R_b): an answer given here is the one the full query would give, only sooner.
template <SupportMapped A, SupportMapped B>
inline bool bounding_ball_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                  const Transform<typename A::Scalar>& pose_b, const Vec3<typename A::Scalar>& ca,
                                  const Vec3<typename A::Scalar>& cb, const Vec3<typename A::Scalar>& delta,
                                  typename A::Scalar dd, typename A::Scalar tf,
                                  GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const S ra = a.bounding_radius(), rb = b.bounding_radius();
    const S slack = tf * (norm1(pose_a.t) + norm1(pose_b.t) + norm1(ca) + norm1(cb) + ra + rb);
    const S outer = ra + rb + slack;
    if (dd > outer * outer) {
        const S len = std::sqrt(dd);
        const S gap = len - outer;
        if (!(gap > S(0))) return false;
        const S inv = S(1) / len;
        const Vec3<S> n(-delta[0] * inv, -delta[1] * inv, -delta[2] * inv);  // A towards B
        r.iterations = 0;
        r.simplex.size = 0;
        r.status = GjkStatus::separated;
        r.distance = gap;
        r.normal = n;
        r.point_a = plus_scaled(ca, ra, n);
        r.point_b = plus_scaled(cb, -rb, n);
        return true;
    }
    const S inner = a.inner_radius() + b.inner_radius() - slack;
    if (inner > S(0) && dd < inner * inner) {
        r.iterations = 0;
        r.simplex.size = 0;
        r.status = GjkStatus::intersecting;
        r.distance = S(0);
        return true;
    }
    return false;
}

/// The containment certificate of the cold boolean query (`GjkSettings::containment_test`): true when the first
/// simplex vertex's point of B (`x.b`, A's frame) lies inside A, or its point of A (`x.a`) inside B, by more than the
/// slack — a point of one shape strictly inside the other proves overlap, no tetrahedron around the origin
/// needed (the P3 overlaps are 1e-5…1e-2 of the size: GJK needs 5.5 to 10 rounds for the tetrahedron, while
/// the first support pair, along the centre line, is the deepest pair often enough, see docs/convex.md). Only
/// the first pair is tested: a test in every round of the loop saved more rounds on cylinders and cones but
/// cost the separated ("close") queries 5–13 % (the loop's code, not the tests' flops). Slack: that of
/// `bounding_ball_decides` with the radii counted twice, tf·(|t_a|₁ + |t_b|₁ + 2(R_a + R_b)); a point taken
/// into the other frame is off by a few ε of |t_a| + |t_b| + its distance from its own centre, the shape's
/// test rounds by a few ε of its size, and the slack is at least gjk_finish's touching tolerance (256ε·|w|,
/// |w| ≤ |t_b − t_a| + R_a + R_b + the centres' offsets): a pair within that tolerance of touching is never
/// called intersecting here.
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE typename A::Scalar containment_slack(const A& a, const Transform<typename A::Scalar>& pose_a,
                                                         const B& b, const Transform<typename A::Scalar>& pose_b,
                                                         typename A::Scalar tf) noexcept {
    using S = typename A::Scalar;
    // At least 16ε, so that a touch_factor of 0 still leaves the transforms' rounding covered.
    const S t = std::max(tf, S(16) * std::numeric_limits<S>::epsilon());
    return t * (norm1(pose_a.t) + norm1(pose_b.t) + S(2) * (a.bounding_radius() + b.bounding_radius()));
}
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE bool containment_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                             const Transform<typename A::Scalar>& pose_b,
                                             const GjkVertex<typename A::Scalar>& x,
                                             const Vec3<typename A::Scalar>& a_in_b,
                                             typename A::Scalar tf) noexcept {
    using S = typename A::Scalar;
    // B's point is already in A's frame (x.b); A's point in B's frame is a_in_b (unused unless B has the test).
    // Both tests evaluated (no short circuit: which one holds is data-dependent), first without the slack: on
    // separated pairs the points lie outside, and the slack (two sqrt for the radii) is only paid for a candidate.
    auto inside = [&](S slack) {
        bool in = false;
        if constexpr (HasContainmentTest<A>) in = a.contains_strictly(x.b, slack);
        if constexpr (HasContainmentTest<B>) in = in | b.contains_strictly(a_in_b, slack);
        return in;
    };
    if (!inside(S(0))) return false;
    // At least 16ε, so that a touch_factor of 0 still leaves the transforms' rounding covered.
    const S t = std::max(tf, S(16) * std::numeric_limits<S>::epsilon());
    return inside(t * (norm1(pose_a.t) + norm1(pose_b.t) + S(2) * (a.bounding_radius() + b.bounding_radius())));
}
/// The same for shapes that locate points by walking (HasPointLocation, a hull): one pass with the slack, B's
/// location first and A's only when B does not contain A's point, each walk starting among the triangles around
/// the shape's first support vertex (`hint_a`, `hint_b`). The face planes the points were found beyond are
/// returned (`axis_a`, A's frame; `axis_b`, B's; zero if none) for candidate_axes_decide. Out of line: inlined
/// into the cold query it slowed the separated pairs by 12 % even when it returned at once (layout, not work).
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE bool containment_decides_walking(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const GjkVertex<typename A::Scalar>& x, const Vec3<typename A::Scalar>& a_in_b, typename A::Scalar tf,
    std::uint32_t hint_a, std::uint32_t hint_b, Vec3<typename A::Scalar>& axis_a,
    Vec3<typename A::Scalar>& axis_b) noexcept {
    const typename A::Scalar slack = containment_slack(a, pose_a, b, pose_b, tf);
    if constexpr (HasPointLocation<B>) {
        const auto where = b.locate(a_in_b, slack, hint_b);
        if (where.inside) return true;
        axis_b = where.axis;
    } else if constexpr (HasContainmentTest<B>) {
        if (b.contains_strictly(a_in_b, slack)) return true;
    }
    if constexpr (HasPointLocation<A>) {
        const auto where = a.locate(x.b, slack, hint_a);
        axis_a = where.axis;
        return where.inside;
    } else if constexpr (HasContainmentTest<A>) {
        return a.contains_strictly(x.b, slack);
    }
    return false;
}

/// The containment certificate on a support pair of the cold boolean's loop (`x`, A's frame; `rel` B's pose in A's
/// frame), for pairs of shapes with cheap tests and no candidate axes: shallow overlaps of curved shapes, whose
/// first pair is often on a rim or apex and not inside, have a point inside the other shape after a few rounds
/// (P3 cylinder / cone overlaps: 7.7 → 5.6 and 6.1 → 4.9 rounds). Out of line: a test in every round inlined into
/// the loop cost the separated pairs 5–13 % (the loop's code; tenth session), out of line 1–3 % in the A/B driver.
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE bool loop_containment_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                             const Transform<typename A::Scalar>& pose_b,
                                             const Transform<typename A::Scalar>& rel,
                                             const GjkVertex<typename A::Scalar>& x, typename A::Scalar tf) noexcept {
    const Vec3<typename A::Scalar> a_in_b = rotate_back(rel.R, minus(x.a, rel.t));
    return containment_decides(a, pose_a, b, pose_b, x, a_in_b, tf);
}

/// The boolean queries' plane test in squares: v·w/|v| > margin + tf·max(size, margin) (tf = touch_factor·ε,
/// the threshold gjk_finish uses) with vv = |v|² and size2 = size², so that a failing test costs no sqrt (none at
/// all without margins).
template <class S>
CDKIT_ALWAYS_INLINE bool plane_separates_squared(S vw, S vv, S size2, S margin, S tf) noexcept {
    if (!(vw > S(0))) return false;
    S thr2;
    if (margin > S(0)) {
        const S thr = margin + tf * std::max(std::sqrt(size2), margin);
        thr2 = thr * thr;
    } else {
        thr2 = tf * tf * size2;
    }
    return vw * vw > thr2 * vv;
}

/// The candidate-axis test of the cold boolean query (`GjkSettings::candidate_axes`): the face normal of A towards
/// B's first support point (`x.b`, A's frame), the one of B towards A's (`a_in_b`, B's frame) and, where both
/// shapes name edges, the cross product of their edges nearest those points, each given the loop's plane test
/// along that direction d (A's frame): the support point w of D along −d with d·w > (margin + tol)·|d|, tol as in
/// the loop with the points' magnitudes counted in the size. Such a plane proves separation whatever d is, so the
/// answer is the one the loop would certify, only sooner. Why these: on close box pairs the closest features are
/// a vertex and a face, or two edges, whose face normal or edge cross product is then the separating axis (and,
/// below a gap of about the features' rounding, the only one; Gottschalk, Lin, Manocha, "OBBTree: a hierarchical
/// structure for rapid interference detection", SIGGRAPH 1996, the separating axis theorem for boxes); the
/// first support pair along the centre line is usually at those features. GJK reaches the same plane only after
/// 3–6 simplex steps. A cone's face normal at the other point's azimuth does the same for a rim or the apex
/// against its side or base (P3 cone close 114 → 91–97 ns). True, with `r` filled in as the loop's early exit, when
/// a plane is found; `pairs` counts the support pairs used (kept apart from the loop's counter, which schedules
/// its momentum).
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE bool candidate_axes_decide(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                               const Transform<typename A::Scalar>& rel,
                                               const GjkVertex<typename A::Scalar>& x,
                                               const Vec3<typename A::Scalar>& a_in_b,
                                               const Vec3<typename A::Scalar>& located_a,
                                               const Vec3<typename A::Scalar>& located_b, typename A::Scalar size2,
                                               typename A::Scalar tf, int& pairs,
                                               GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    auto plane_along = [&](const Vec3<S>& d) {
        ++pairs;
        const Vec3<S> pa = core_support(a, neg(d));
        const Vec3<S> pb_local = core_support(b, rotate_back(rel.R, d));
        const Vec3<S> pb = place(rel, pb_local);
        const Vec3<S> w = minus(pa, pb);
        const S w2 = norm2(w);
        if (!(w2 <= std::numeric_limits<S>::max())) return false;  // NaN or inf: the loop will report it
        // The size the tolerance scales with: |w| and the magnitudes the rounding of w acts on (A's point, B's
        // point in its own frame and the translation that moves it into A's). On a touching pair w is tiny, and
        // |w| alone would let a gap at the level of that rounding pass as a plane.
        const S sz2 = std::max(std::max(std::max(size2, w2), norm2(pa)), std::max(norm2(pb_local), norm2(rel.t)));
        const S dw = dot3(d, w);
        const S dd = norm2(d);
        if (!plane_separates_squared(dw, dd, sz2, margin, tf)) return false;
        const S inv = S(1) / std::sqrt(dd);
        const Vec3<S> n = Vec3<S>(-d[0] * inv, -d[1] * inv, -d[2] * inv);  // A towards B, in A's frame
        r.iterations = 1 + pairs;
        r.status = GjkStatus::separated;
        r.distance = dw * inv - margin;
        r.normal = rotate(pose_a.R, n);
        r.point_a = place(pose_a, plus_scaled(pa, ma, n));
        r.point_b = place(pose_a, plus_scaled(pb, -mb, n));
        return true;
    };
    // B lies outside A's face n_a, so D = A − B lies on the −n_a side; A outside B's face n_b: on the +n_b side.
    // First the faces a hull's point location found the points beyond (`located_a`, A's frame; `located_b`, B's;
    // zero when none): on close hull pairs with a vertex–face contact that face is the separating axis.
    if constexpr (HasPointLocation<A>) {
        if (norm2(located_a) > S(0) && plane_along(neg(located_a))) return true;
    }
    if constexpr (HasPointLocation<B>) {
        if (norm2(located_b) > S(0) && plane_along(rotate(rel.R, located_b))) return true;
    }
    if constexpr (HasCandidateAxes<A>) {
        if (plane_along(neg(Vec3<S>(a.candidate_axis(x.b))))) return true;
    }
    if constexpr (HasCandidateAxes<B>) {
        if (plane_along(rotate(rel.R, Vec3<S>(b.candidate_axis(a_in_b))))) return true;
    }
    // Both faces failed: an edge–edge contact, whose separating axis is the cross product of the two edges
    // nearest the other shape's point (skipped for near-parallel edges), turned so that D's first point lies on
    // its positive side (where all of D must lie if it separates).
    if constexpr (HasCandidateEdges<A> && HasCandidateEdges<B>) {
        const Vec3<S> c = cross3(Vec3<S>(a.candidate_edge(x.b)), rotate(rel.R, Vec3<S>(b.candidate_edge(a_in_b))));
        if (norm2(c) > S(1e-6)) {
            if (plane_along(dot3(c, x.w) < S(0) ? neg(c) : c)) return true;
        }
    }
    (void)x;
    (void)a_in_b;
    (void)located_a;
    (void)located_b;
    return false;
}

/// One support pair of the boolean queries' world-frame first step: A's point along `da` (A's frame), B's along
/// v (world axes, B's frame after the rotation), both placed; then the plane test of the cold query's loop along
/// v, the direction from B towards A (`plane_separates_squared`, with |w| and then the points' world magnitudes
/// as the size). The returned step: `separated`, `r` holds the separated result (status, lower-bound distance,
/// world normal, the two shapes' extreme points along it), all but the iteration count; `open`, no plane, the
/// pair's points are for the caller's next step; `non_finite`, w is NaN or infinite. Shared by the cold query's
/// first iteration (v the centre line, da = R_aᵀ·(−v)) and the warm query's cached direction (da the cached one,
/// v = −R_a·da: the same bits as that query had on its own). Returned by value, the caller copying the points
/// into locals: filled through a reference, the cold query kept them in memory (hull pairs 4–12 % slower).
enum class WorldStep { separated, open, non_finite };
template <class S> struct WorldPair {
    Vec3<S> sa, sb;  ///< the support points, each in its shape's frame
    S size2;         ///< |w|², w = A's point − B's in world axes
    WorldStep step;
};
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE WorldPair<typename A::Scalar> world_plane_step(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                               const Transform<typename A::Scalar>& pose_b,
                                               const Vec3<typename A::Scalar>& v, typename A::Scalar vv,
                                               const Vec3<typename A::Scalar>& da, typename A::Scalar tf,
                                               std::uint32_t* hints, GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    WorldPair<S> pair;
    pair.sa = core_support_hinted(a, da, hints);
    pair.sb = core_support_hinted(b, rotate_back(pose_b.R, v), hints + 1);
    const Vec3<S> pa = place(pose_a, pair.sa), pb = place(pose_b, pair.sb);
    const Vec3<S> w = minus(pa, pb);
    pair.size2 = norm2(w);
    pair.step = WorldStep::non_finite;
    if (!(pair.size2 <= std::numeric_limits<S>::max())) return pair;
    const S vw = dot3(v, w);
    // The tolerance scales with the magnitudes whose rounding w carries: world coordinates, up to |t| away from
    // the origin. |w| alone shrinks to nothing on a touching pair and let a rounding-level gap pass as a plane
    // (a cone–hull pair at gap 0, 100 sizes from the origin: "separated" at 2e-16 of the size). The |w| test
    // first: the magnitudes are only needed when it passes.
    if (!(plane_separates_squared(vw, vv, pair.size2, margin, tf) &&
          plane_separates_squared(vw, vv, std::max(pair.size2, std::max(norm2(pa), norm2(pb))), margin, tf))) {
        pair.step = WorldStep::open;
        return pair;
    }
    const S inv = S(1) / std::sqrt(vv);
    const Vec3<S> n = Vec3<S>(-v[0] * inv, -v[1] * inv, -v[2] * inv);  // A towards B
    r.status = GjkStatus::separated;
    r.distance = vw * inv - margin;
    r.normal = n;
    r.point_a = plus_scaled(pa, ma, n);
    r.point_b = plus_scaled(pb, -mb, n);
    pair.step = WorldStep::separated;
    return pair;
}

/// The warm boolean query's first test (a cache from an earlier frame), in world axes: a fresh support pair
/// along the cache's first direction (the last separating one), with the plane test of gjk_intersect_cold's
/// first step — no relative pose, no square root unless it separates, the result's normal and points already
/// in world axes. The loop's former test of that direction (A's frame, square roots for the bound and the
/// tolerance, the result rotated back) made a warm boolean dearer than a cold one on separated frames (126 vs
/// 96 ns in the coherent benchmark). True, with `r` and the cache's hints set, when the pair separates
/// (iterations 0); otherwise the pair goes into the cache's first slot for the loop (see below).
template <SupportMapped A, SupportMapped B>
inline bool warm_direction_separates(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                     const Transform<typename A::Scalar>& pose_b,
                                     const GjkSettings<typename A::Scalar>& settings,
                                     GjkCache<typename A::Scalar>& cache, GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const S tf = settings.touch_factor * std::numeric_limits<S>::epsilon();
    const Vec3<S>& d = cache.directions[0];  // A's support direction (towards B), A's frame
    const Vec3<S> v = neg(rotate(pose_a.R, d));  // from B towards A in world axes, as the cold query's centre line
    std::uint32_t hints[2] = {cache.hint_a, cache.hint_b};
    const WorldPair<S> pair = world_plane_step(a, pose_a, b, pose_b, v, norm2(v), d, tf, hints, r);
    switch (pair.step) {
        case WorldStep::separated:
            r.iterations = 0;
            r.simplex.size = 0;
            cache.hint_a = hints[0];
            cache.hint_b = hints[1];
            return true;
        case WorldStep::open:
            // No plane: the pair is this frame's point of D along the cached direction. In the cache's first
            // slot (when its points are these shapes') the loop rebuilds it there instead of querying it again.
            if (cache.shape_a == static_cast<const void*>(&a) && cache.shape_b == static_cast<const void*>(&b)) {
                cache.point_a[0] = pair.sa;
                cache.point_b[0] = pair.sb;
            }
            return false;
        case WorldStep::non_finite: break;  // gjk_loop's checks decide
    }
    return false;
}

/// Cold boolean query (no cache): the loop of `gjk_loop` reduced to what a yes/no answer needs, with the
/// early exit's result built in place. The separation test compares squares (v·w > (margin + tol)·|v| needs
/// no sqrt; the margin-free case none at all), the one sqrt and division are paid when a plane is found; no
/// lower-bound bookkeeping, no cache, no wide-type refinement in the loop. The certificates are those of
/// gjk_loop: a support point w along −v with v·w > (margin + tol)·|v| proves separation for any v; four points
/// of D around the origin prove overlap. Since every support point was given the plane test, an exit on |v|
/// (gap test, repeated point, no progress) beyond the tolerance has no plane: `certify_separation` decides it.
/// Out of line from the bounding-ball pre-test (`gjk_intersect_cold`, below): inlined there, the body's register
/// pressure made GCC load both rotations up front and spill them in shuffled copies, which the pairs the balls
/// decide paid for nothing (a hull pair: 355 instructions per query, 220 with the split; 52 → 17–28 ns in P3's
/// hull1000 distant cell). vw_dir = c_a − c_b, the world centres' difference, and vv = |vw_dir|², the
/// pre-test's values, as the first direction.
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE void gjk_intersect_cold_search(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                              const Transform<typename A::Scalar>& pose_b,
                                              const GjkSettings<typename A::Scalar>& settings,
                                              Vec3<typename A::Scalar> vw_dir, typename A::Scalar vv,
                                              GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    using Solver = SimplexSolver<S>;
    const S eps = std::numeric_limits<S>::epsilon();
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    const S tf = settings.touch_factor * eps;
    GjkSimplex<S>& s = r.simplex;
    s.size = 0;
    // Hill-climbing hints between iterations: a polyhedron tries the previous support vertex with one scan of
    // its neighbours and otherwise climbs from its direction table (ConvexPolyhedron::support_index).
    std::uint32_t hints[2] = {std::uint32_t(-1), std::uint32_t(-1)};
    auto separates = [&](S vw, S vv, S size2) { return plane_separates_squared(vw, vv, size2, margin, tf); };
    // First iteration in the world frame, along the line between the centres (a separating direction for
    // most distant pairs): one support pair decides them without the relative pose, and the exit's normal
    // and supporting points are already world-frame (no transforms back).
    if (!(vv > S(0)) || !(vv <= std::numeric_limits<S>::max())) { vw_dir = Vec3<S>::UnitX(); vv = S(1); }
    const Vec3<S> da = rotate_back(pose_a.R, neg(vw_dir));  // A's support direction, A's frame
    const WorldPair<S> pair = world_plane_step(a, pose_a, b, pose_b, vw_dir, vv, da, tf, hints, r);
    switch (pair.step) {
        case WorldStep::separated: r.iterations = 1; return;
        case WorldStep::non_finite:
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::degenerate;
            r.distance = S(0);
            return;
        case WorldStep::open: break;
    }
    const Vec3<S> sa = pair.sa, sb = pair.sb;
    S size2 = pair.size2;
    // Otherwise the loop, in A's frame, from that support point.
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    {
        GjkVertex<S>& x = s.v[0];
        x.a = sa;
        x.b_local = sb;
        x.b = place(rel, sb);
        x.w = minus(x.a, x.b);
        x.d = da;
        s.size = 1;
        s.lambda[0] = S(1);
    }
    // From here on in A's frame: the rounding of w is that of A's and B's local points and of rel's translation,
    // so a plane or a touching verdict is judged against those magnitudes too (|w| alone vanishes on touching
    // pairs). Computed when a plane test passes or the loop ends, not on every round.
    auto with_magnitudes = [&](S sz2) { return std::max(std::max(sz2, norm2(sa)), std::max(norm2(sb), norm2(rel.t))); };
    // A's first support point in B's frame, for B's containment test and candidate axis.
    Vec3<S> a_in_b = Vec3<S>::Zero();
    if constexpr (HasContainmentTest<B> || HasCandidateAxes<B>) a_in_b = rotate_back(rel.R, minus(sa, rel.t));
    Vec3<S> axis_a = Vec3<S>::Zero(), axis_b = Vec3<S>::Zero();  // face planes a point location found (A's, B's frame)
    if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> && (HasPointLocation<A> || HasPointLocation<B>)) {
        if (settings.containment_test && containment_decides_walking(a, pose_a, b, pose_b, s.v[0], a_in_b, tf, hints[0],
                                                                     hints[1], axis_a, axis_b)) {
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
    } else if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> &&
                         (HasContainmentTest<A> || HasContainmentTest<B>)) {
        if (settings.containment_test && containment_decides(a, pose_a, b, pose_b, s.v[0], a_in_b, tf)) {
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
    }
    Vec3<S> v = s.v[0].w;
    vv = norm2(v);
    if (!(vv > tf * tf * size2)) {
        r.iterations = 1;
        gjk_finish(a, pose_a, b, settings, r, GjkStatus::touching, v, std::sqrt(size2), S(0), s.v[0], true);
        return;
    }
    int candidate_pairs = 0;  // support pairs spent on candidate axes, reported in the iteration count
    if constexpr (HasCandidateAxes<A> || HasCandidateAxes<B> || HasPointLocation<A> || HasPointLocation<B>) {
        if (settings.candidate_axes && candidate_axes_decide(a, pose_a, b, rel, s.v[0], a_in_b, axis_a, axis_b, size2,
                                                             tf, candidate_pairs, r))
            return;
    }
    int it = 1;
    typename Solver::Sel sel;
    GjkStatus status = GjkStatus::max_iterations;
    // Nesterov momentum (Montaut et al., RSS 2022, "Collision detection accelerated: an optimization
    // perspective"): query along d_k = δ_k d_{k−1} + (1 − δ_k) y_k with
    // y_k = δ_k v_k + (1 − δ_k) w_k (w_k the last support point), δ_k = (k + 1)/(k + 3), instead of along v_k.
    // The boolean certificates do not depend on the direction (a plane is proven by the direction actually
    // queried; overlap by four points of D around the origin), so momentum only changes the work. When it
    // stalls (a repeated point, or a point that does not shorten v) it is switched off and the query goes on
    // as plain GJK, whose convergence tests need w to be the support along −v.
    // Not on margin pairs: their cores are points and segments (spheres, capsules), polytopes on which plain
    // GJK ends in two or three iterations; momentum took close capsule pairs from 2.3 to 3.0.
    bool momentum = settings.momentum_iterations > 1 && !(margin > S(0));
    // Solver::apply moving only the fields this loop and gjk_finish read (a, b, w; not d and b_local, which
    // only the cache uses and which this loop does not write).
    auto apply_lean = [&s](const typename Solver::Sel& r_) {
        for (int k = 0; k < r_.size; ++k) {
            const std::size_t from = std::size_t(r_.idx[std::size_t(k)]);
            if (from != std::size_t(k)) {
                s.v[std::size_t(k)].a = s.v[from].a;
                s.v[std::size_t(k)].b = s.v[from].b;
                s.v[std::size_t(k)].w = s.v[from].w;
            }
            s.lambda[std::size_t(k)] = r_.lambda[std::size_t(k)];
        }
        s.size = r_.size;
    };
    Vec3<S> d_prev = Vec3<S>(-da), w_last = s.v[0].w;
    while (it < settings.max_iterations) {
        ++it;
        Vec3<S> d = v;
        if (momentum && it > settings.momentum_iterations) momentum = false;
        if (momentum) {
            const S k = S(it - 1);
            const S delta = (k + S(1)) / (k + S(3));
            const S c = S(1) - delta;
            for (int k3 = 0; k3 < 3; ++k3) d[k3] = delta * d_prev[k3] + c * (delta * v[k3] + c * w_last[k3]);
        }
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        {
            // As minkowski_support_into without the two fields only the cache reads (d, b_local).
            const Vec3<S> nd = neg(d);
            x.a = core_support_hinted(a, nd, hints);
            x.b = place(rel, Vec3<S>(core_support_hinted(b, rotate_back(rel.R, d), hints + 1)));
            x.w = minus(x.a, x.b);
        }
        const S w2 = norm2(x.w);
        if (!(w2 <= std::numeric_limits<S>::max())) { status = GjkStatus::degenerate; break; }  // NaN or inf
        size2 = std::max(size2, w2);
        const S dw = dot3(d, x.w);
        const S dd = momentum ? norm2(d) : vv;
        if (separates(dw, dd, size2) && separates(dw, dd, with_magnitudes(size2))) {
            const S inv = S(1) / std::sqrt(dd);
            const Vec3<S> n = Vec3<S>(-d[0] * inv, -d[1] * inv, -d[2] * inv);  // A towards B, in A's frame
            r.iterations = it + candidate_pairs;
            r.status = GjkStatus::separated;
            r.distance = dw * inv - margin;
            r.normal = rotate(pose_a.R, n);
            r.point_a = place(pose_a, plus_scaled(x.a, ma, n));
            r.point_b = place(pose_a, plus_scaled(x.b, -mb, n));
            return;
        }
        // Each round's support pair gets the containment test too where both shapes have a cheap one and curved
        // cores (cylinders, cones: their rounds are many on shallow overlaps; on boxes it cost more than it saved).
        if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> && !HasPointLocation<A> && !HasPointLocation<B> &&
                      !HasPolytopeCore<A> && !HasPolytopeCore<B> && HasContainmentTest<A> && HasContainmentTest<B>) {
            if (settings.containment_test && loop_containment_decides(a, pose_a, b, pose_b, rel, x, tf)) {
                r.iterations = it + candidate_pairs;
                r.status = GjkStatus::intersecting;
                r.distance = S(0);
                s.size = 0;
                return;
            }
        }
        bool duplicate = false;
        for (int i = 0; i < s.size; ++i) {
            const Vec3<S>& q = s.v[std::size_t(i)].w;
            duplicate = duplicate || (q[0] == x.w[0] && q[1] == x.w[1] && q[2] == x.w[2]);
        }
        if (momentum) {
            d_prev = d;
            if (duplicate) { momentum = false; continue; }
        } else {
            // Converged on |v| (v a point of D): as gjk_loop; gjk_finish then decides touching / separated.
            if (gap_converged(vv, dw, margin, size2, settings.rel_tolerance)) {
                status = GjkStatus::separated;
                break;
            }
            if (duplicate) { status = GjkStatus::separated; break; }
        }
        const int old_size = s.size++;
        if (s.size == 4) Solver::tetrahedron_newest_last(s, sel);
        else Solver::select(s, sel);
        if (sel.inside) {  // overlap proven: the result gjk_finish would build, without its call
            r.iterations = it + candidate_pairs;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
        const S nvv = norm2(sel.v);
        if (!(nvv == nvv)) { s.size = old_size; status = GjkStatus::degenerate; break; }
        if (nvv <= tf * tf * size2) { apply_lean(sel); v = sel.v; status = GjkStatus::touching; break; }
        if (!(nvv < vv)) {
            s.size = old_size;
            if (momentum) { momentum = false; continue; }
            status = GjkStatus::separated;
            break;
        }
        w_last = s.v[std::size_t(old_size)].w;
        apply_lean(sel);
        v = sel.v;
        vv = nvv;
    }
    r.iterations = it + candidate_pairs;
    size2 = with_magnitudes(size2);
    // gjk_finish decides an overlap of the margins on |v| (|v| − margin below −tol), which needs v on the simplex:
    // on a sliver triangle the double step can put it well inside (a capsule of radius 1e-9 beside a 1e-11 wide
    // box, 1e-9 of the size apart: |v| 7.0e-10 in double, 1.07e-9 in long double, and "intersecting" for a
    // separated pair; found by the seeded hard-case count). Where the step's rounding could reach across the
    // margin, it is redone in the wider type. Only on these exits, and only for margins and a final triangle.
    if constexpr (!std::is_same_v<S, wider_t<S>>) {
        if (margin > S(0) && s.size == 3 && status != GjkStatus::degenerate) {
            const S across = std::sqrt(norm2(v)) - margin;
            if (sliver_step_may_reach(s, across * across)) {
                typename Solver::Sel fin;
                if (refine_step(s, 2, fin, true)) {
                    v = fin.v;
                    vv = norm2(v);
                    // Beyond the margins now: claimed only with a plane, as for any exit on |v| (below).
                    if (status == GjkStatus::touching && separation_claimed(vv, margin, tf, size2))
                        status = GjkStatus::separated;
                }
            }
        }
    }
    // Every support plane was tested above with gjk_finish's threshold, so a "separated" exit here (gap test,
    // repeated point, no progress) has no plane behind it: certify it unless |v| already lies within the
    // tolerance (then gjk_finish answers touching, or intersecting inside the margins: no separation claimed).
    if (status == GjkStatus::separated && separation_claimed(vv, margin, tf, size2)) {
        finish_certified(a, pose_a, b, pose_b, settings, r, v, size2, S(0), hints[0], hints[1], true);
        return;
    }
    GjkVertex<S> none;
    none.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    gjk_finish(a, pose_a, b, settings, r, status, v, std::sqrt(size2), S(0), none, true);
    if (r.status == GjkStatus::touching) prove_touching_overlap(a, b, Transform<S>(rel), r);
}

/// A shape seen in the wider type of `refine_near_contact`: the directions are rounded to the shape's own type,
/// its support points widened exactly. For a primitive the points are the shape's own (a rounded direction picks a
/// point optimal for a direction within an ulp's angle); a wrapper's (Transformed, Inflated) carry its own double
/// rounding.
template <SupportMapped A> struct WidenedShape {
    using Narrow = typename A::Scalar;
    using Scalar = wider_t<Narrow>;
    const A* shape;
    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return Vec3<Narrow>(shape->support(d.template cast<Narrow>())).template cast<Scalar>();
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return Vec3<Narrow>(shape->center()).template cast<Scalar>(); }
    [[nodiscard]] Scalar margin() const noexcept
        requires HasMargin<A>
    {
        return Scalar(shape->margin());
    }
    [[nodiscard]] Vec3<Scalar> core_support(const Vec3<Scalar>& d) const noexcept
        requires HasMargin<A>
    {
        return Vec3<Narrow>(shape->core_support(d.template cast<Narrow>())).template cast<Scalar>();
    }
};

/// `s` in its scalar's wider type: `s.widened()` where the shape has it, else a `WidenedShape` view.
template <SupportMapped A> [[nodiscard]] auto widened_shape(const A& s) noexcept {
    if constexpr (HasWidened<A>) {
        return s.widened();
    } else {
        return WidenedShape<A>{&s};
    }
}

/// The poses of a double query's retry in `wider_t` (`refine_near_contact`, EPA's `refine_penetration`): world axes
/// with the origin moved to A's, so that B's offset t_b − t_a is exact or nearly in the wider type and the rounding
/// stays ε_W of the relative coordinates, however far from the world's origin the shapes are.
template <class S> struct WideningFrame {
    using W = wider_t<S>;
    Vec3<W> origin;          ///< A's position: add it to the retry's world points
    Transform<W> pose_a;     ///< A's rotation, at the origin
    Transform<W> pose_b;     ///< B's rotation, at t_b − t_a
    WideningFrame(const Transform<S>& a, const Transform<S>& b)
        : origin(a.t.template cast<W>()),
          pose_a(a.R.template cast<W>(), Vec3<W>::Zero()),
          pose_b(b.R.template cast<W>(), Vec3<W>(b.t.template cast<W>() - origin)) {}
};

/// S's touching tolerance factor (tf·ε_S) in units of the wider type's ε: a retry does not call a pair separated
/// below the threshold the S query applies.
template <class S> [[nodiscard]] inline wider_t<S> widened_touch_factor(S touch_factor) noexcept {
    using W = wider_t<S>;
    return W(touch_factor) * W(std::numeric_limits<S>::epsilon()) / std::numeric_limits<W>::epsilon();
}

/// True when a separated distance query in double should be refined in long double (`refine_near_contact`).
/// `magnitude`: of the coordinates the loop worked with in A's frame, |t_rel|₁ + size (size = the largest |w|);
/// they carry rounding of about ε·magnitude (the relative pose, B's points mapped into A's frame). Measured
/// (docs/convex.md), the double answer is off by up to ~24ε·magnitude/distance where a core is curved (the loop
/// stops at its convergence floor: 1e-8 relative at a distance of 1e-7 between shapes 0.4 apart) and ~ε·magnitude/
/// distance on two polytope cores (it ends on the closest simplex; only the final rounding): refine where 32 and 2
/// times that exceed the tolerance. The distance, not the cores' |v|: a margin (capsule, sphere) leaves |v|'s
/// absolute rounding on a distance that is much smaller. Also refined: a loop that stopped short of its tolerance
/// (`tolerance_met` false: gap above 4× the tolerance at a repeated point, no progress or the rounding floor of
/// v·w, which is ε·size², not ε·magnitude, where D is long and thin: a needle pair came out 5e-9 relative too far).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] inline bool near_contact_needs_refinement(const GjkSettings<typename A::Scalar>& settings,
                                                        const GjkResult<typename A::Scalar>& r,
                                                        typename A::Scalar magnitude, bool tolerance_met) noexcept {
    using S = typename A::Scalar;
    constexpr S floor = HasPolytopeCore<A> && HasPolytopeCore<B> ? S(2) : S(32);
    return settings.refine_near_contact && r.status == GjkStatus::separated &&
           (!tolerance_met ||
            floor * std::numeric_limits<S>::epsilon() * magnitude > settings.rel_tolerance * r.distance);
}

/// Whether queries in S have a near-contact refinement: double, where long double is wider (x87 or quad).
template <class S>
inline constexpr bool refines_near_contact =
    std::is_same_v<S, double> && std::numeric_limits<long double>::digits > std::numeric_limits<double>::digits;

/// Cold boolean query (no cache): the bounding-ball pre-test (`GjkSettings::bounding_ball_test`), then
/// `gjk_intersect_cold_search` from the centre line.
template <SupportMapped A, SupportMapped B>
inline void gjk_intersect_cold(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                               const Transform<typename A::Scalar>& pose_b,
                               const GjkSettings<typename A::Scalar>& settings,
                               GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const Vec3<S> ca = world_center(a, pose_a), cb = world_center(b, pose_b);
    const Vec3<S> delta = minus(ca, cb);
    const S dd = norm2(delta);
    if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B>) {
        if (settings.bounding_ball_test && dd <= std::numeric_limits<S>::max() &&
            bounding_ball_decides(a, pose_a, b, pose_b, ca, cb, delta, dd,
                                  settings.touch_factor * std::numeric_limits<S>::epsilon(), r))
            return;
    }
    gjk_intersect_cold_search(a, pose_a, b, pose_b, settings, delta, dd, r);
}

template <SupportMapped A, SupportMapped B>
GjkResult<typename A::Scalar> gjk_query(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                        const Transform<typename A::Scalar>& pose_b,
                                        GjkCache<typename A::Scalar>* cache,
                                        const GjkSettings<typename A::Scalar>& settings, bool boolean,
                                        bool retry_cached_direction = true) noexcept;

/// The near-contact refinement of a separated double distance query: GJK again in long double on the same
/// shapes (`widened_shape`), in world axes (both shapes placed by their poses: the double loop's frame of A
/// takes R_aᵀ for R_a's inverse, off by the rotation's rounding, ~1e-16 of the coordinates — as much as the
/// answer's last digits at a distance of 1e-7), warm-started from the double query's final simplex (a few
/// iterations), with the same tolerance, which the wider arithmetic can now reach. Its result replaces `r` when
/// it is separated (a long-double "touching" or failure keeps the double answer). Out of line: rare, and off the
/// loop's code.
template <SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH void refine_near_contact(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                         const Transform<typename A::Scalar>& pose_b,
                                         const GjkSettings<typename A::Scalar>& settings,
                                         GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    using W = wider_t<S>;
    // The shapes in long double: rebuilt there when they can be (`HasWidened`: a curved primitive's rounded
    // support point is off its surface by ε of its size, 1e-9 relative at 1e-8 of distance), otherwise their double
    // support points widened.
    const auto wa = widened_shape(a);
    const auto wb = widened_shape(b);
    const WideningFrame<S> frame(pose_a, pose_b);
    const Vec3<W>& origin = frame.origin;
    const Transform<W>& pa = frame.pose_a;
    const Transform<W>& pb = frame.pose_b;
    const Transformed<decltype(wa)> ta{wa, pa};
    const Transformed<decltype(wb)> tb{wb, pb};
    const Transform<W> world;  // identity: B "in A's frame" is B in these world axes
    // The final simplex's directions (A's frame → world) start the loop; its points are queried again.
    GjkCache<W> cache;
    cache.size = std::min(r.simplex.size, 4);
    for (int i = 0; i < cache.size; ++i)
        cache.directions[std::size_t(i)] = rotate(pa.R, Vec3<W>(r.simplex.v[std::size_t(i)].d.template cast<W>()));
    GjkSettings<W> ws;
    ws.max_iterations = settings.max_iterations;
    ws.rel_tolerance = W(settings.rel_tolerance);
    ws.touch_factor = widened_touch_factor(settings.touch_factor);  // the double query's 256ε·size
    // The distance query in W (no refinement of its own: W is the widest type).
    const GjkResult<W> wr = gjk_query(ta, world, tb, world, &cache, ws, false);
    r.iterations += wr.iterations;
    if (wr.status != GjkStatus::separated) return;
    r.distance = S(wr.distance);
    r.normal = wr.normal.template cast<S>();
    r.point_a = Vec3<W>(wr.point_a + origin).template cast<S>();
    r.point_b = Vec3<W>(wr.point_b + origin).template cast<S>();
    // The simplex back in A's frame (its documented frame; informational for a separated result).
    r.simplex.size = wr.simplex.size;
    for (int i = 0; i < wr.simplex.size; ++i) {
        const GjkVertex<W>& x = wr.simplex.v[std::size_t(i)];
        GjkVertex<S>& y = r.simplex.v[std::size_t(i)];
        const Vec3<W> xa = rotate_back(pa.R, Vec3<W>(x.a - pa.t)), xb = rotate_back(pa.R, Vec3<W>(x.b - pa.t));
        y.a = xa.template cast<S>();
        y.b = xb.template cast<S>();
        y.w = Vec3<W>(xa - xb).template cast<S>();
        y.d = rotate_back(pa.R, x.d).template cast<S>();
        y.b_local = rotate_back(pb.R, Vec3<W>(x.b - pb.t)).template cast<S>();
        r.simplex.lambda[std::size_t(i)] = S(wr.simplex.lambda[std::size_t(i)]);
    }
}

template <SupportMapped A, SupportMapped B>
GjkResult<typename A::Scalar> gjk_query(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                        const Transform<typename A::Scalar>& pose_b,
                                        GjkCache<typename A::Scalar>* cache,
                                        const GjkSettings<typename A::Scalar>& settings,
                                        bool boolean, bool retry_cached_direction) noexcept {
    using S = typename A::Scalar;
    GjkResult<S> r;
    if (boolean && !cache) {
        gjk_intersect_cold(a, pose_a, b, pose_b, settings, r);
        r.colliding = is_colliding(r.status);
        return r;
    }
    if (boolean && retry_cached_direction && cache->size > 0) {
        if (warm_direction_separates(a, pose_a, b, pose_b, settings, *cache, r)) return r;  // separated
        // Tried, in world axes: the loop starts from the rebuilt cache (its first slot now holds that pair).
    }
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    const S margin = margin_of(a) + margin_of(b);
    Vec3<S> v;
    S size, lower;
    GjkVertex<S> sep;
    sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    bool tolerance_met = true;
    GjkStatus st = boolean ? gjk_loop<true, true>(a, b, rel, settings, cache, margin, r.simplex, v, size,
                                                  r.iterations, lower, cache ? settings.warm_exit_quality : S(0),
                                                  &sep, nullptr)
                           : gjk_loop<true, false>(a, b, rel, settings, cache, margin, r.simplex, v, size,
                                                   r.iterations, lower, S(0), &sep, &tolerance_met);
    gjk_finish(a, pose_a, b, settings, r, st, v, size, lower, sep, boolean);
    if (r.status == GjkStatus::touching) prove_touching_overlap(a, b, rel, r);
    if constexpr (refines_near_contact<S>) {
        if (!boolean && near_contact_needs_refinement<A, B>(
                            settings, r, size + std::abs(rel.t[0]) + std::abs(rel.t[1]) + std::abs(rel.t[2]),
                            tolerance_met))
            refine_near_contact(a, pose_a, b, pose_b, settings, r);
    }
    r.colliding = is_colliding(r.status);
    return r;
}

}  // namespace detail

/// Separation distance between shape `a` placed by `pose_a` and shape `b` placed by `pose_b`, with
/// closest points and normal in the world frame. `separated` is certified as for gjk_intersect (some support
/// plane bound exceeded the touching tolerance, else the wide-type continuation decides, else `touching`);
/// the distance and normal are those of the closest point |v|. Const, noexcept, thread-safe; `cache`
/// (optional, caller-owned, per pair) warm-starts the search and is updated.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_distance(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, false);
}

/// Boolean intersection test with early exit as soon as a separating plane is found. `status` is
/// `separated`, `touching` or `intersecting` (or `max_iterations`/`degenerate`); `colliding` says touching or intersecting.
/// Guarantee: `separated` is only answered with a proven plane — a direction u and a support point w of A − B
/// along −u with u·w/|u| above the touching tolerance (256ε·size; van den Bergen 1999's lower bound), or
/// disjoint bounding balls; `normal` is that direction and `distance` that bound (≤ the true distance, up to
/// the support maps' rounding). When GJK stops without such a plane (near contact on curved shapes, where the
/// double sub-simplex step can misplace v), the query goes on with the steps in a wider type
/// (`detail::certify_separation`) and, if that decides nothing, answers `touching`: conservative for collision
/// detection, and only pairs within the rounding of contact get there. `intersecting` is answered with four
/// points of A − B around the origin, a point of one shape strictly inside the other, overlapping inner
/// balls / margins, or — where the loop ended touching on a triangle or segment through the origin (nested
/// needles) — five support points of A − B around it (`detail::touching_simplex_proves_overlap`).
/// Const, noexcept, thread-safe; `cache` as for gjk_distance.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_intersect(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, true);
}

}  // namespace cdkit

// The built-in shapes' GJK queries in double are compiled into libcdkit (precompiled_queries.hpp).
#ifndef CDKIT_NO_PRECOMPILED_QUERIES
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/precompiled_queries.hpp>
namespace cdkit {
CDKIT_FOR_EACH_BUILTIN_PAIR(CDKIT_GJK_QUERY_INSTANCE, extern)
}  // namespace cdkit
#endif
