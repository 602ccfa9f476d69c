// The candidate-axis test of the cold boolean GJK (GjkSettings::candidate_axes, HasCandidateAxes): a box names its
// face normal and its nearest edge towards the other shape's first support point, a cone its base or its side's
// normal at that point's azimuth, and GJK tries the face normals and (two boxes, HasCandidateEdges) the edges'
// cross product with its plane test before the loop. Checked: the box's and the cone's choices; no "separated"
// from it for pairs placed by long-double GJK at a gap of 0 or below
// (down to −1e-2 of the size, incl. ±1e-12, ±1e-9), scale ratios up to 1e6, offsets up to 100 sizes; every
// candidate exit's plane really separates (long double) and its distance is that plane's gap; the status equals the
// plain loop's (candidate axes off) wherever the plain loop is decisive; and it decides a fair share of close box
// pairs (the P3 "close" band, gaps 1e-4 … 1e-1 of the shape size).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "convex_reference.hpp"
#include "near_contact_pose.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <random>
#include <type_traits>
#include <vector>

using namespace cdkit;

namespace {

using L = long double;

using test::random_unit;

/// True when `n` (world, unit) is ± a column of R to 1e-12: a box's face normal, which is what a candidate exit
/// reports (the loop's directions are simplex points, not face normals, except by coincidence).
bool is_face_normal(const Vec3<double>& n, const Mat3<double>& R) {
    for (int j = 0; j < 3; ++j)
        if (std::abs(std::abs(n.dot(Vec3<double>(R.col(j)))) - 1.0) < 1e-12) return true;
    return false;
}
/// True when `n` is orthogonal to a column of Ra and to one of Rb (to 1e-12): the cross product of two box edges.
bool is_edge_cross(const Vec3<double>& n, const Mat3<double>& Ra, const Mat3<double>& Rb) {
    bool a = false, b = false;
    for (int j = 0; j < 3; ++j) {
        a = a || std::abs(n.dot(Vec3<double>(Ra.col(j)))) < 1e-12;
        b = b || std::abs(n.dot(Vec3<double>(Rb.col(j)))) < 1e-12;
    }
    return a && b;
}
/// True when `n` is ± a face normal of `s` (a box's axes, a hull's face normals) turned by R, to 1e-12.
template <class Shape> bool is_shape_face_normal(const Shape& s, const Mat3<double>& R, const Vec3<double>& n) {
    if constexpr (std::is_same_v<Shape, Box<double>>) {
        return is_face_normal(n, R);
    } else if constexpr (std::is_same_v<Shape, Cone<double>>) {
        // The base's −e_z, or a side normal (2h·u, r)/√(4h² + r²): its axial component is r/√(4h² + r²).
        const double nz = n.dot(Vec3<double>(R.col(2)));
        const double side = s.radius / std::sqrt(4 * s.half_height * s.half_height + s.radius * s.radius);
        return std::abs(nz + 1.0) < 1e-12 || std::abs(nz - side) < 1e-12;
    } else if constexpr (std::is_same_v<Shape, ConvexPolyhedron<double>>) {
        for (std::uint32_t f = 0; f < s.face_count(); ++f)
            if (std::abs(std::abs(n.dot(R * s.face_normal(f))) - 1.0) < 1e-12) return true;
        return false;
    } else {
        (void)s, (void)R, (void)n;
        return false;
    }
}
/// A candidate-axis exit: "separated" after the first pair and at most three candidate pairs, along a face normal
/// of either shape (a box's or a cone's, or a hull's found by its point location) or (two boxes) an edge cross
/// product.
template <class A, class B>
bool candidate_exit(const GjkResult<double>& r, const A& a, const Transform<double>& pa, const B& b,
                    const Transform<double>& pb) {
    if (r.status != GjkStatus::separated || r.iterations < 2 || r.iterations > 4) return false;
    const bool boxes = std::is_same_v<A, Box<double>> && std::is_same_v<B, Box<double>>;
    return is_shape_face_normal(a, pa.R, r.normal) || is_shape_face_normal(b, pb.R, r.normal) ||
           (boxes && is_edge_cross(r.normal, pa.R, pb.R));
}

/// n points at radii 0.1·[inner, 1] in random directions, and their long-double copies (for hulls).
std::pair<std::vector<Vec3<double>>, std::vector<Vec3<L>>> shell_cloud(std::mt19937_64& rng, int n, double inner) {
    std::vector<Vec3<double>> cloud;
    for (int i = 0; i < n; ++i)
        cloud.push_back(random_unit(rng) * (0.1 * std::uniform_real_distribution<double>(inner, 1)(rng)));
    std::vector<Vec3<L>> cloud_l;
    for (const auto& q : cloud) cloud_l.push_back(q.cast<L>());
    return {cloud, cloud_l};
}

struct Tally {
    int cases = 0, candidate_exits = 0, claimed_at_contact = 0, unbacked = 0, bad_distance = 0, bad_points = 0;
    int differ = 0, close_box = 0, close_box_decided = 0, close_hulls = 0, close_hulls_decided = 0;
    int close_cones = 0, close_cones_decided = 0, placed_apart = 0;
};

/// One pair at the relative gaps g (distance g·size, size = R_a + R_b), placed by long-double GJK on the double
/// poses' long-double copies (as test_gjk_certified_separation.cpp does).
template <class A, class AL, class B, class BL>
void run_pair(const A& a, const AL& a_l, const B& b, const BL& b_l, bool boxes, std::mt19937_64& rng, Tally& t) {
    GjkSettings<double> plain;
    plain.candidate_axes = false;
    GjkSettings<L> exact;
    exact.rel_tolerance = L(1e-16);
    const double size = a.bounding_radius() + b.bounding_radius();
    for (const double g : {1e-2, 1e-3, 1e-4, 1e-6, 1e-9, 1e-12, 0.0, -1e-12, -1e-9, -1e-6, -1e-3, -1e-2}) {
        Transform<double> pa, pb;
        if (!test::place_near_contact(a_l, b_l, size, g, rng, pa, pb)) continue;
        const Transform<L> pa_l(pa.R.template cast<L>(), pa.t.template cast<L>());
        ++t.cases;
        const Transform<L> pb_l(pb.R.template cast<L>(), pb.t.template cast<L>());
        const auto ref = gjk_distance(a_l, pa_l, b_l, pb_l, nullptr, exact);
        const bool decisive = ref.status == GjkStatus::intersecting ||
                              (ref.status == GjkStatus::separated && ref.distance > L(1e-10 * size));
        const auto on = gjk_intersect(a, pa, b, pb);
        const auto off = gjk_intersect(a, pa, b, pb, nullptr, plain);
        // The plain loop's answer wherever it is decisive and right; elsewhere (within the rounding of contact) the
        // candidate may only have found a plane the loop could not certify, which the checks below examine.
        if (decisive && off.colliding == ref.colliding && on.status != off.status) ++t.differ;
        const bool candidate = candidate_exit(on, a, pa, b, pb);
        if (boxes && g >= 1e-4) {
            ++t.close_box;
            t.close_box_decided += candidate;
        }
        if (std::is_same_v<A, ConvexPolyhedron<double>> && std::is_same_v<B, ConvexPolyhedron<double>> && g >= 1e-4) {
            ++t.close_hulls;
            t.close_hulls_decided += candidate;
        }
        if (std::is_same_v<A, Cone<double>> && std::is_same_v<B, Cone<double>> && g >= 1e-4) {
            ++t.close_cones;
            t.close_cones_decided += candidate;
        }
        if (!candidate) continue;
        ++t.candidate_exits;
        // Touching or overlapping: no plane can separate beyond the tolerance. Where the reference finds the pair
        // apart after all (a small shape pushed past a cone's apex comes out beyond it; a placement at 0 by
        // long-double GJK on a sharp apex ends a few ulps apart), the plane checks below judge the answer.
        if (g <= 0) {
            if (ref.status == GjkStatus::separated) ++t.placed_apart;
            else ++t.claimed_at_contact;
        }
        // The plane: the supporting planes of A and B orthogonal to the normal are apart (up to the double
        // rounding of the poses and support maps), and the reported distance is that gap.
        const L gap = test::supporting_plane_gap(a_l, pa_l, b_l, pb_l, on.normal.template cast<L>());
        t.unbacked += !(gap > L(0));
        const double tol = 1e-13 * (size + pa.t.norm() + pb.t.norm());
        t.bad_distance += !(std::abs(double(gap) - on.distance) <= tol && on.distance > 0);
        // point_a / point_b lie on those planes: A's extreme point along the normal and B's against it.
        const Vec3<double>& n = on.normal;
        const double ea = double(n.template cast<L>().dot(Transformed<AL>{a_l, pa_l}.support(n.template cast<L>())));
        const double eb = double(n.template cast<L>().dot(Transformed<BL>{b_l, pb_l}.support(-n.template cast<L>())));
        t.bad_points += !(std::abs(n.dot(on.point_a) - ea) <= tol && std::abs(n.dot(on.point_b) - eb) <= tol);
    }
}

}  // namespace

TEST_CASE("box candidate axis is the face that a point lies farthest outside of", "[gjk][candidate]") {
    const Box<double> box(Vec3<double>(0.1, 0.2, 0.3));
    CHECK(box.candidate_axis(Vec3<double>(0.15, 0.0, 0.0)) == Vec3<double>(1, 0, 0));
    CHECK(box.candidate_axis(Vec3<double>(-0.15, 0.22, 0.0)) == Vec3<double>(-1, 0, 0));
    CHECK(box.candidate_axis(Vec3<double>(-0.15, -0.3, 0.0)) == Vec3<double>(0, -1, 0));
    CHECK(box.candidate_axis(Vec3<double>(0.0, 0.1, -0.35)) == Vec3<double>(0, 0, -1));
    // Farthest outside, not largest coordinate: z is larger but y is farther beyond its face.
    CHECK(box.candidate_axis(Vec3<double>(0.0, 0.25, 0.31)) == Vec3<double>(0, 1, 0));
    // Always a unit axis, also for points inside, on the centre, or not finite.
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (int i = 0; i < 100; ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        CHECK(box.candidate_axis(p).norm() == 1.0);
    }
    CHECK(box.candidate_axis(Vec3<double>::Zero()).norm() == 1.0);
    CHECK(box.candidate_axis(Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN())).norm() == 1.0);
    // The nearest edges: p beyond the x and y faces is nearest the edge along z.
    CHECK(box.candidate_edge(Vec3<double>(0.15, 0.25, 0.1)) == Vec3<double>(0, 0, 1));
    CHECK(box.candidate_edge(Vec3<double>(-0.11, 0.0, -0.4)) == Vec3<double>(0, 1, 0));
    CHECK(box.candidate_edge(Vec3<double>(0.0, -0.3, 0.35)) == Vec3<double>(1, 0, 0));
    for (int i = 0; i < 100; ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        CHECK(box.candidate_edge(p).norm() == 1.0);
    }
    CHECK(box.candidate_edge(Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN())).norm() == 1.0);
}

TEST_CASE("cone candidate axis is its base or its side at the point's azimuth", "[gjk][candidate]") {
    const Cone<double> cone(0.1, 0.2);  // base z = −0.2 of radius 0.1, apex z = 0.2; side normal ∝ (0.4·u, 0.1)
    // Below the base: −e_z; beside the side: the side normal at p's azimuth, whatever p's height.
    CHECK(cone.candidate_axis(Vec3<double>(0.01, 0.02, -0.3)) == Vec3<double>(0, 0, -1));
    auto side = [&](double x, double y, double z) { return cone.candidate_axis(Vec3<double>(x, y, z)).normalized(); };
    CHECK(side(0.3, 0.0, 0.0).isApprox(Vec3<double>(0.4, 0, 0.1).normalized()));
    CHECK(side(0.0, -0.3, -0.1).isApprox(Vec3<double>(0, -0.4, 0.1).normalized()));
    CHECK(side(0.0, 0.0, 0.5).isApprox(Vec3<double>(0.4, 0, 0.1).normalized()));  // on the axis: e_x's azimuth
    // Below the rim, farther beyond the base's plane than the side's: the base; farther beside: the side.
    CHECK(cone.candidate_axis(Vec3<double>(0.12, 0.0, -0.35)) == Vec3<double>(0, 0, -1));
    CHECK(cone.candidate_axis(Vec3<double>(0.3, 0.0, -0.21))[2] > 0);
    // Always finite and non-zero, also on the axis, inside, at the centre, or for a point not finite.
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (int i = 0; i < 100; ++i) {
        const Vec3<double> a = cone.candidate_axis(Vec3<double>(u(rng), u(rng), u(rng)));
        CHECK((a.allFinite() && a.norm() > 0.09));
    }
    CHECK(cone.candidate_axis(Vec3<double>::Zero()).norm() > 0.09);
    const Vec3<double> nan = cone.candidate_axis(Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN()));
    CHECK((nan.allFinite() && nan.norm() > 0.09));
}

TEST_CASE("candidate axes never claim a plane at contact, and their planes separate", "[gjk][candidate]") {
    std::mt19937_64 rng(1906);
    std::uniform_real_distribution<double> u(0.05, 0.1);
    const auto [cloud, cloud_l] = shell_cloud(rng, 40, 0.3);
    const ConvexPolyhedron<double> hull(cloud);
    const ConvexPolyhedron<L> hull_l(cloud_l);
    // A second hull, of 300 points (about 60 vertices: hill climbing and the walk's vertex fans), for hull pairs.
    const auto [cloud2, cloud2_l] = shell_cloud(rng, 300, 0.5);
    const ConvexPolyhedron<double> hull2(cloud2);
    const ConvexPolyhedron<L> hull2_l(cloud2_l);
    Tally t;
    for (int k = 0; k < test::scaled(60, 8); ++k) {
        // B scaled by 10^j, j ∈ [−3, 3]: scale ratios up to 1e6 between the pairs' extremes.
        const double s = std::pow(10.0, std::uniform_int_distribution<int>(-3, 3)(rng));
        const double r1 = u(rng), r2 = u(rng), h1 = u(rng), h2 = u(rng);
        const Vec3<double> e1(r1, h1, r2), e2(h2, r1, h1);
        run_pair(Box<double>(e1), Box<L>(e1.cast<L>()), Box<double>(e2), Box<L>(e2.cast<L>()), true, rng, t);
        run_pair(Box<double>(e1), Box<L>(e1.cast<L>()), Box<double>(s * e2), Box<L>((s * e2).cast<L>()), false, rng, t);
        run_pair(Box<double>(e1), Box<L>(e1.cast<L>()), Cylinder<double>(s * r2, s * h2), Cylinder<L>(s * r2, s * h2),
                 false, rng, t);
        run_pair(Cone<double>(r1, h1), Cone<L>(r1, h1), Box<double>(s * e2), Box<L>((s * e2).cast<L>()), false, rng, t);
        run_pair(hull, hull_l, Box<double>(e2), Box<L>(e2.cast<L>()), false, rng, t);
        run_pair(hull, hull_l, hull2, hull2_l, false, rng, t);
        run_pair(Cone<double>(s * r1, s * h1), Cone<L>(s * r1, s * h1), hull2, hull2_l, false, rng, t);
        run_pair(Box<double>(e1), Box<L>(e1.cast<L>()), Capsule<double>(s * r2 / 2, s * h2), Capsule<L>(s * r2 / 2, s * h2),
                 false, rng, t);
        run_pair(Sphere<double>(s * r2), Sphere<L>(s * r2), Box<double>(e1), Box<L>(e1.cast<L>()), false, rng, t);
        run_pair(Box<double>(e1), Box<L>(e1.cast<L>()), Ellipsoid<double>(e2), Ellipsoid<L>(e2.cast<L>()), false, rng, t);
        run_pair(Cone<double>(r1, h1), Cone<L>(r1, h1), Cone<double>(r2, h2), Cone<L>(r2, h2), false, rng, t);
        run_pair(Cylinder<double>(r2, h1), Cylinder<L>(r2, h1), Cone<double>(s * r1, s * h2), Cone<L>(s * r1, s * h2),
                 false, rng, t);
    }
    INFO(t.cases << " cases, " << t.candidate_exits << " candidate exits; close box pairs " << t.close_box_decided
                 << " of " << t.close_box << ", close hull pairs " << t.close_hulls_decided << " of " << t.close_hulls
                 << ", close cone pairs " << t.close_cones_decided << " of " << t.close_cones
                 << " decided by a candidate axis; " << t.placed_apart << " candidate exits at g <= 0 where the "
                 << "reference finds the pair apart");
    CHECK(t.cases >= test::scaled(60, 8) * 12 * 12 * 9 / 10);
    CHECK(t.claimed_at_contact == 0);
    CHECK(t.unbacked == 0);
    CHECK(t.bad_distance == 0);
    CHECK(t.bad_points == 0);
    CHECK(t.differ == 0);
    // Not a pass by never firing: close box pairs are vertex–face or edge–edge contacts, decided by a face normal
    // or an edge cross product (65 % of them at scale 1).
    CHECK(t.candidate_exits > 0);
    CHECK(t.close_box_decided >= t.close_box * 2 / 5);
    // Hull pairs: the face a point location finds the other's support point beyond (vertex–face contacts).
    CHECK(t.close_hulls_decided >= t.close_hulls / 5);
    // Cone pairs: a rim or the apex against the other's side or base (43 of 180 at scale 1; the 24 pairs of the
    // reduced run are too few for a share, so there it only has to fire).
    CHECK(t.close_cones_decided >= (t.close_cones >= 100 ? t.close_cones / 6 : 1));
}

TEST_CASE("candidate axes agree with the plain loop on random pairs", "[gjk][candidate]") {
    // Random poses over ±0.2 with shapes of size ~0.1: separated, close and overlapping pairs; every status with
    // the candidate axes must equal the plain loop's.
    std::mt19937_64 rng(1907);
    std::uniform_real_distribution<double> u(0.05, 0.1), t(-0.2, 0.2);
    GjkSettings<double> plain;
    plain.candidate_axes = false;
    int n = 0, differ = 0, separated = 0, candidate = 0;
    auto run = [&](const auto& a, const auto& b) {
        const Transform<double> pa(test::random_rotation(rng), Vec3<double>(t(rng), t(rng), t(rng)));
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(t(rng), t(rng), t(rng)));
        const auto on = gjk_intersect(a, pa, b, pb);
        const auto off = gjk_intersect(a, pa, b, pb, nullptr, plain);
        ++n;
        differ += on.status != off.status;
        separated += on.status == GjkStatus::separated;
        candidate += candidate_exit(on, a, pa, b, pb);
    };
    std::vector<Vec3<double>> cloud;
    for (int i = 0; i < 60; ++i) cloud.push_back(random_unit(rng) * (0.1 * std::uniform_real_distribution<double>(0.3, 1)(rng)));
    const ConvexPolyhedron<double> hull(cloud);
    for (int k = 0; k < test::scaled(2000, 200); ++k) {
        const Vec3<double> e1(u(rng), u(rng), u(rng)), e2(u(rng), u(rng), u(rng));
        run(Box<double>(e1), Box<double>(e2));
        run(Box<double>(e1), Cylinder<double>(e2[0], e2[1]));
        run(Cone<double>(e2[0], e2[1]), Box<double>(e1));
        run(hull, Box<double>(e1));
        run(hull, hull);
        run(Cone<double>(e2[0], e2[1]), hull);
        run(Box<double>(e1), Capsule<double>(e2[0] / 2, e2[1]));
        run(Ellipsoid<double>(e2), Box<double>(e1));
        run(Cone<double>(e1[0], e1[1]), Cone<double>(e2[0], e2[2]));
    }
    INFO(n << " pairs, " << separated << " separated, " << candidate << " by a candidate axis");
    CHECK(differ == 0);
    CHECK(separated > n / 5);
    CHECK(candidate > n / 100);
}
