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
///
/// The parts (narrowphase/gjk/): types.hpp (settings, cache, simplex, result), query.hpp (gjk_distance,
/// gjk_intersect), detail/simplex_solver.hpp (the sub-simplex step), detail/certify.hpp (exit tests and
/// certification), detail/loop.hpp (the loop), detail/pretests.hpp (bounding balls, containment, candidate axes),
/// detail/cold_search.hpp (the cold boolean), detail/widening.hpp (the long-double retry GJK and EPA share).

#include <cdkit/narrowphase/gjk/types.hpp>
#include <cdkit/narrowphase/gjk/query.hpp>
