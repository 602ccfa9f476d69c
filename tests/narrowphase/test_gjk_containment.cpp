// The containment certificate of the cold boolean GJK (GjkSettings::containment_test): the shapes' strict
// containment tests are conservative (a point they accept has a ball of radius `slack` around it inside the
// shape, checked against the support map) and not useless; the certificate never fires on a pair that is apart
// or touching (placed by long-double GJK at 1e-12 of its size and at 0, scale ratios up to 1e6, offsets up to 100
// sizes), never contradicts long-double GJK, never turns a right answer of the plain loop wrong, gives the plain
// loop's status on random pairs (where the loop said "touching" it may prove "intersecting"), and decides most
// shallow box overlaps after one support pair; with the plain loop certified, neither is ever wrong where
// long-double GJK decides. Hulls (a walk through the tetrahedra centre–triangle, ConvexPolyhedron::locate) are
// checked against every face plane in long double, from every start, near vertices and far from the origin.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "near_contact_pose.hpp"
#include "test_common.hpp"

#include <random>

using namespace cdkit;

namespace {

using test::random_unit;

/// Random points around the shape (inside and outside, some near the boundary); for each accepted point
/// (contains_strictly(p, slack)) every sampled support plane lies at least `slack` beyond it:
/// n·p + slack ≤ n·s(n) for unit n. Returns how many points were accepted. `jitter` (relative to the bounding
/// radius) moves the points off the rays from the centre through the support points: a hull's walk cannot
/// certify points on those rays (they lie on the planes between its tetrahedra) and answers false there.
template <class Shape> int check_conservative(const Shape& s, std::mt19937_64& rng, double slack, double jitter = 0) {
    const double R = s.bounding_radius();
    const Vec3<double> c = s.center();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int accepted = 0, violated = 0;
    const int points = test::scaled(400, 40), normals = test::scaled(400, 60);
    std::vector<Vec3<double>> dirs;
    for (int j = 0; j < normals; ++j) dirs.push_back(random_unit(rng));
    for (int k = 0; k < 3; ++k)
        for (double sg : {-1.0, 1.0}) {
            Vec3<double> n = Vec3<double>::Zero();
            n[k] = sg;
            dirs.push_back(n);
        }
    for (int i = 0; i < points; ++i) {
        // A support point pulled towards the centre by a factor in [0.9, 1] (near the boundary) or [0, 1].
        const Vec3<double> q = s.support(random_unit(rng));
        const double f = i % 2 ? 1 - 0.1 * u(rng) : u(rng);
        Vec3<double> p = c + f * (q - c);
        if (jitter > 0) p += jitter * R * random_unit(rng);
        if (!s.contains_strictly(p, slack)) continue;
        ++accepted;
        for (const Vec3<double>& n : dirs)
            if (n.dot(p) + slack > n.dot(Vec3<double>(s.support(n))) + 1e-15 * R) ++violated;
    }
    CHECK(violated == 0);
    // The boundary of the shrunk shape itself: a point exactly on the boundary is never accepted.
    for (const Vec3<double>& n : dirs) CHECK_FALSE(s.contains_strictly(Vec3<double>(s.support(n)), slack));
    return accepted;
}

}  // namespace

TEST_CASE("strict containment tests are conservative and not useless", "[gjk][containment]") {
    std::mt19937_64 rng(701);
    for (double slack : {0.0, 1e-12, 1e-3}) {
        INFO("slack " << slack);
        const int points = test::scaled(400, 40);
        CHECK(check_conservative(Box<double>(Vec3<double>(0.1, 0.3, 0.05)), rng, slack) > points / 4);
        CHECK(check_conservative(Cylinder<double>(0.1, 0.3), rng, slack) > points / 4);
        CHECK(check_conservative(Cylinder<double>(0.3, 0.02), rng, slack) > points / 5);
        CHECK(check_conservative(Cone<double>(0.1, 0.3), rng, slack) > points / 5);
        CHECK(check_conservative(Cone<double>(0.3, 0.05), rng, slack) > points / 5);
        CHECK(check_conservative(Cone<double>(0.2, 0.2), rng, slack) > points / 5);
    }
    // Hulls (point location by a walk): round, thin (a slab 1e-3 thick) and far from their frame's origin.
    std::uniform_real_distribution<double> radial(0.5, 1.0);
    std::vector<Vec3<double>> round, thin, far;
    for (int i = 0; i < 200; ++i) {
        const Vec3<double> q = random_unit(rng) * 0.1 * radial(rng);
        round.push_back(q);
        thin.push_back(Vec3<double>(q[0], q[1], 1e-2 * q[2]));
        far.push_back(q + Vec3<double>(300.0, -200.0, 50.0));
    }
    for (double slack : {0.0, 1e-12, 1e-3}) {
        INFO("hulls, slack " << slack);
        const int points = test::scaled(400, 40);
        // (A hull walk also needs the slack from its tetrahedra's sides: fewer points pass at slack 1e-3.)
        CHECK(check_conservative(ConvexPolyhedron<double>(round), rng, slack, 0.05) > points / 8);
        // The slab is at most 2e-3 thick: a slack of 1e-3 leaves no point with its ball inside, smaller ones many
        // (the walk's answers at slack 0 are judged in exact arithmetic in test_gjk_exact_oracle_cgal.cpp).
        const int thin_accepted = check_conservative(ConvexPolyhedron<double>(thin), rng, slack, 0.05);
        if (slack >= 1e-3) CHECK(thin_accepted == 0);
        else CHECK(thin_accepted > points / 20);
        CHECK(check_conservative(ConvexPolyhedron<double>(far), rng, slack, 0.05) > points / 8);
    }
    // A slack larger than the shape accepts nothing (a negative shrunk radius must not square to a positive one).
    const Cylinder<double> cyl(0.1, 0.3);
    CHECK_FALSE(cyl.contains_strictly(Vec3<double>::Zero(), 0.2));
    const Cone<double> cone(0.1, 0.3);
    CHECK_FALSE(cone.contains_strictly(Vec3<double>(0, 0, -0.1), 0.2));
    CHECK(cone.contains_strictly(Vec3<double>(0, 0, -0.1), 0.01));
    const Box<double> box(Vec3<double>(0.1, 0.2, 0.3));
    CHECK_FALSE(box.contains_strictly(Vec3<double>::Zero(), 0.1));
    CHECK(box.contains_strictly(Vec3<double>::Zero(), 0.099));
}

TEST_CASE("hull point location is conservative against every face plane, and its axes are planes p lies beyond",
          "[gjk][containment]") {
    // Against the exact answer up to long double: the least distance from p to the hull's supporting planes (each
    // computed in long double from three vertices). `inside` needs that distance above the slack; an `axis` must
    // be an outward face normal whose plane p lies beyond (beyond every vertex along it); every start (no hint, a
    // random vertex, the support vertex towards p, an out-of-range index) must be conservative, and deep points
    // (more than slack + 1e-9 of the size inside) must be found from all of them.
    using L = long double;
    std::mt19937_64 rng(704);
    std::uniform_real_distribution<double> u(0.0, 1.0), radial(0.5, 1.0);
    int wrong_inside = 0, wrong_axis = 0, deep = 0, deep_found = 0, outside = 0, outside_axis = 0;
    const int round_hulls = test::scaled(12, 3), sliver_hulls = test::scaled(24, 6);
    for (int h = 0; h < round_hulls + sliver_hulls; ++h) {
        std::vector<Vec3<double>> cloud;
        if (h < round_hulls) {
            const int n = h % 3 == 0 ? 8 : (h % 3 == 1 ? 100 : 2000);
            const Vec3<double> offset = h % 4 == 3 ? Vec3<double>(1e3, -2e3, 5e2) : Vec3<double>::Zero();
            for (int i = 0; i < n; ++i) cloud.push_back(offset + random_unit(rng) * radial(rng));
        } else {
            // Sliver triangles: two pentagons (a prism's caps, turned and moved at random), each with three
            // corners 1e-8 … 1e-6 apart on a line up to 1e-13 … 1e-16 off it. The sign of a side plane's
            // determinant det(v_e − c, v_e+1 − c, v_e+2 − c) is lost to rounding there (a first version trusted
            // it and accepted a point 0.3 outside such a hull).
            const double sz = std::pow(10.0, -6 - 2 * u(rng)), eta = std::pow(10.0, -13 - 3 * u(rng));
            const double xy[5][2] = {{0, -1.37 * sz}, {eta, 0.3 * sz}, {0, sz}, {-1.2345678, 0.987654321},
                                     {-0.91234567, -1.07654321}};
            const Mat3<double> R = test::random_rotation(rng);
            const Vec3<double> offset = 0.1 * random_unit(rng);
            for (const double z : {1.0, -0.8765431})
                for (const auto& q : xy) cloud.push_back(R * Vec3<double>(q[0], q[1], z) + offset);
        }
        const ConvexPolyhedron<double> hull(cloud);
        const auto& V = hull.vertices();
        // The reference planes: the hull triangles' (outward unit normal, offset). On the sliver hulls Qhull's merged
        // faces are not flat and their fans not convex (a vertex 1e-3 beyond a fan triangle's plane), so there the
        // hull's supporting planes are found by brute force over vertex triples instead (every vertex on one side,
        // to 1e-13): a point inside them is in conv(V). (The walk's tetrahedra lie in conv(V) either way.)
        std::vector<std::pair<Vec3<L>, L>> planes;
        const bool slivers = h >= round_hulls;
        if (!slivers) {
            for (const auto& t : hull.triangles()) {
                const Vec3<L> a = V[t[0]].cast<L>(), b = V[t[1]].cast<L>(), c = V[t[2]].cast<L>();
                const Vec3<L> nn = (b - a).cross(c - a).normalized();
                planes.emplace_back(nn, nn.dot(a));
            }
        } else {
            for (std::size_t i = 0; i < V.size(); ++i)
                for (std::size_t j = i + 1; j < V.size(); ++j)
                    for (std::size_t k = j + 1; k < V.size(); ++k) {
                        const Vec3<L> a = V[i].cast<L>(), b = V[j].cast<L>(), c = V[k].cast<L>();
                        Vec3<L> nn = (b - a).cross(c - a);
                        if (!(nn.norm() > L(0))) continue;
                        nn.normalize();
                        L lo = 0, hi = 0;
                        for (const auto& v : V) {
                            lo = std::min(lo, nn.dot(v.cast<L>() - a));
                            hi = std::max(hi, nn.dot(v.cast<L>() - a));
                        }
                        if (hi <= L(1e-13)) planes.emplace_back(nn, nn.dot(a));
                        else if (lo >= L(-1e-13)) planes.emplace_back(-nn, -nn.dot(a));
                    }
        }
        for (int i = 0; i < test::scaled(4000, 400); ++i) {
            // Around a support point: pulled in, pushed out, or jittered (near faces, edges and vertices).
            const Vec3<double> d = random_unit(rng);
            const Vec3<double> c = hull.center(), q = hull.support(d);
            const int kind = h < round_hulls ? i % 4 : i % 5;
            // (Off the rays from the centre through the vertices by 1e-6: points on them lie on the planes
            // between the walk's tetrahedra, which it cannot certify; it answers false there, see check_conservative.)
            Vec3<double> p = kind == 0 ? Vec3<double>(c + u(rng) * (q - c))
                             : kind == 1 ? Vec3<double>(c + (1.0 + 0.01 * (u(rng) - 0.5)) * (q - c))
                                         : Vec3<double>(q + std::pow(10.0, -12 * u(rng)) * random_unit(rng));
            if (kind == 3) p = c + 1.3 * u(rng) * (p - c);
            if (kind == 4) p = c + 1.6 * Vec3<double>(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);  // anywhere
            if (kind != 2) p += 1e-6 * random_unit(rng);
            const double slack = i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 1e-12 : 1e-4);
            const Vec3<L> pl = p.cast<L>();
            L least = std::numeric_limits<L>::infinity();
            for (const auto& [nn, off] : planes) least = std::min(least, off - nn.dot(pl));
            const std::uint32_t hints[4] = {std::uint32_t(-1), std::uint32_t(rng() % V.size()),
                                            hull.support_index(p - c), std::uint32_t(V.size() + 7)};
            // Deep: inside by more than 1e-9 beyond the slack (a slack of 1e-4 is also needed from the tetrahedron's
            // sides, which a point inside by 1e-4 need not clear: only the conservative checks for it).
            const bool is_deep = !slivers && slack < 1e-4 && least > L(slack) + L(1e-9 * hull.radius());
            deep += is_deep;
            outside += least < 0;
            bool found = true;
            for (std::uint32_t hint : hints) {
                const PointLocation<double> r = hull.locate(p, slack, hint);
                wrong_inside += r.inside && !(least > L(slack));
                found = found && r.inside;
                if (r.axis != Vec3<double>::Zero() && !slivers) {  // (a sliver hull's fan planes need not support it)
                    outside_axis += hint == hints[2];
                    // Beyond the plane through the farthest vertex along the axis, in long double.
                    const Vec3<L> nn = r.axis.cast<L>();
                    L top = -std::numeric_limits<L>::infinity();
                    for (const auto& v : V) top = std::max(top, nn.dot(v.cast<L>()));
                    wrong_axis += r.inside || !(nn.dot(pl) > top - L(1e-15) * (L(1) + pl.norm()));
                    wrong_axis += std::abs(double(nn.norm()) - 1.0) > 1e-12;
                }
            }
            CHECK(hull.contains_strictly(p, slack) == hull.locate(p, slack, std::uint32_t(-1)).inside);
            deep_found += is_deep && found;
        }
    }
    INFO(deep << " deep points, " << deep_found << " found from every start; " << outside << " outside, "
              << outside_axis << " with an axis from the support vertex's fan");
    CHECK(wrong_inside == 0);
    CHECK(wrong_axis == 0);
    CHECK(deep_found == deep);
    CHECK(outside_axis > outside / 4);

    // The first sliver hull found (by review, through Qhull): the point lies 0.309 outside (exact arithmetic).
    const std::vector<Vec3<double>> found = {
        {1.0757394815964596, -0.10142061181686671, 0.02178216509390677},
        {1.0757394947362466, -0.10142046024827708, 0.021782233965589166},
        {1.0757395002439409, -0.10142039671654049, 0.021782262833975836},
        {1.0923574157052462, 0.28926462983473755, 1.553678985191689},
        {0.94588857891786282, -1.4522041207432972, 0.40887681072722637},
        {-0.79267985716821365, 0.071370550996931931, -0.0020168840729095673},
        {-0.79267984402842662, 0.071370702565521554, -0.0020168152012271703},
        {-0.79267983852073232, 0.071370766097258148, -0.0020167863328404978},
        {-0.77606192305942723, 0.46205579264853619, 1.5298799360248725},
        {-0.92253075984681043, -1.2794129579294986, 0.38507776156041001}};
    const ConvexPolyhedron<double> sliver(found);
    const Vec3<double> p(-0.7232367512183846, 0.42161740243479606, 0.13972013473487907);
    CHECK_FALSE(sliver.contains_strictly(p, 0.0));
    for (std::uint32_t k = 0; k < sliver.vertices().size(); ++k) CHECK_FALSE(sliver.locate(p, 0.0, k).inside);
    CHECK(sliver.contains_strictly(Vec3<double>(sliver.center() + Vec3<double>(1e-3, 2e-3, -1e-3)), 0.0));
}

TEST_CASE("containment certificate changes no boolean answer near contact", "[gjk][containment]") {
    // Each pair is placed by long-double GJK (relative tolerance 1e-16, one refinement) so that its distance is
    // g·size along the separating normal, g ∈ {1e-2, 1e-9, 1e-12, 0, −1e-12, −1e-9, −1e-6, −1e-3, −1e-2}
    // (size = R_a + R_b), shape B scaled by 10^k, k ∈ [−3, 3] (scale ratios up to 1e6 between the pairs'
    // extremes), both poses moved by a common offset of 0.1 … 100 sizes (the double poses then round at
    // ≤ 2e-14·size, far below the 1e-12 gaps). The certificate must never fire on a pair that is apart or touching
    // (g ≥ 0: B moved along the closest-point normal to a plane gap g·size ≥ 0 cannot overlap A); where |g| ≥ 1e-9
    // and long-double GJK is decisive, a certified answer must agree with it, and where the plain double loop
    // answers right the answer must equal its answer, status included; and it must decide a fair share of the
    // shallow overlaps.
    using L = long double;
    std::mt19937_64 rng(702);
    std::uniform_real_distribution<double> u(0.5, 1.0);
    GjkSettings<double> off;
    off.containment_test = false;
    GjkSettings<L> exact;
    exact.rel_tolerance = L(1e-16);
    const double gaps[] = {1e-2, 1e-9, 1e-12, 0.0, -1e-12, -1e-9, -1e-6, -1e-3, -1e-2};
    int cases = 0, differ = 0, fired_not_overlapping = 0, overlapping = 0, fired = 0, corrected = 0, both_wrong = 0;
    int certified_wrong = 0, plain_wrong = 0;
    int box_overlaps = 0, box_fired = 0;
    auto run = [&](const auto& a, const auto& b, const auto& a_l, const auto& b_l, bool boxes) {
        for (double g : gaps) {
            const double size = a.bounding_radius() + b.bounding_radius();
            Transform<double> pa, pb;
            if (!test::place_near_contact(a_l, b_l, size, g, rng, pa, pb)) continue;
            const Transform<L> pa_l(pa.R.template cast<L>(), pa.t.template cast<L>());
            ++cases;
            const auto on = gjk_intersect(a, pa, b, pb);
            const auto plain = gjk_intersect(a, pa, b, pb, nullptr, off);
            // A containment exit: intersecting without a simplex (the balls' exit has no iterations).
            const bool certified = on.status == GjkStatus::intersecting && on.iterations >= 1 && on.simplex.size == 0;
            if (g >= 0 && certified) ++fired_not_overlapping;
            if (std::abs(g) >= 1e-9) {
                // Reference: long-double GJK on the double poses. Moving B by more than the distance along the
                // closest-point normal need not make the pair overlap where the contact is at a vertex or an edge
                // of A − B (a cone's apex or rim), so g's sign is not the truth for g < 0; the reference is, where
                // it is decisive (intersecting, or apart by more than 1e-12 of the size).
                const Transform<L> pb_l(pb.R.template cast<L>(), pb.t.template cast<L>());
                const auto ref = gjk_distance(a_l, pa_l, b_l, pb_l, nullptr, exact);
                const bool decisive = ref.status == GjkStatus::intersecting ||
                                      (ref.status == GjkStatus::separated && ref.distance > L(1e-12 * size));
                if (decisive) {
                    const bool truth = ref.colliding;
                    if (on.colliding != truth && certified) ++certified_wrong;
                    // (A "touching" of the plain loop may become "intersecting" when a point is certified strictly
                    // inside the other shape: a proof of overlap beyond the loop's tolerance.)
                    const bool proven_deeper = plain.status == GjkStatus::touching && certified;
                    const bool status_differs = on.status != plain.status && !proven_deeper;
                    if (plain.colliding == truth && (on.colliding != truth || status_differs)) ++differ;
                    if (plain.colliding != truth && on.colliding == truth) ++corrected;
                    if (plain.colliding != truth && on.colliding != truth) ++both_wrong;
                    plain_wrong += plain.colliding != truth;
                }
            }
            if (g <= -1e-6) {
                ++overlapping;
                fired += certified;
                if (boxes) {
                    ++box_overlaps;
                    box_fired += certified;
                }
            }
        }
    };
    for (int k = 0; k < test::scaled(40, 6); ++k) {
        const double s = std::pow(10.0, std::uniform_int_distribution<int>(-3, 3)(rng));
        const double r1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h1 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        const Vec3<double> e1(r1, h1, r2), e2(h2, r1, h1);
        run(Box<double>(e1), Box<double>(e2), Box<L>(e1.cast<L>()), Box<L>(e2.cast<L>()), true);
        run(Box<double>(e1), Box<double>(s * e2), Box<L>(e1.cast<L>()), Box<L>((s * e2).cast<L>()), false);
        run(Cylinder<double>(r1, h1), Cone<double>(s * r2, s * h2), Cylinder<L>(r1, h1), Cone<L>(s * r2, s * h2), false);
        run(Cone<double>(r1, h1), Cone<double>(r2, h2), Cone<L>(r1, h1), Cone<L>(r2, h2), false);
        run(Cylinder<double>(r1, h1), Cylinder<double>(r2, h2), Cylinder<L>(r1, h1), Cylinder<L>(r2, h2), false);
        run(Ellipsoid<double>(e1), Cylinder<double>(s * r2, s * h2), Ellipsoid<L>(e1.cast<L>()),
            Cylinder<L>(s * r2, s * h2), false);
        run(Cone<double>(s * r1, s * h1), Box<double>(e2), Cone<L>(s * r1, s * h1), Box<L>(e2.cast<L>()), false);
        if (k % 4 == 0) {
            // Hulls of 40 and 400 points (walks from the support vertices' fans), and a cone against one.
            std::vector<Vec3<double>> c1, c2;
            for (int i = 0; i < 40; ++i) c1.push_back(random_unit(rng) * 0.1 * u(rng));
            for (int i = 0; i < 400; ++i) c2.push_back(random_unit(rng) * 0.1 * s * u(rng));
            std::vector<Vec3<L>> c1l, c2l;
            for (const auto& q : c1) c1l.push_back(q.cast<L>());
            for (const auto& q : c2) c2l.push_back(q.cast<L>());
            const ConvexPolyhedron<double> h1d(c1), h2d(c2);
            const ConvexPolyhedron<L> h1l(c1l), h2l(c2l);
            for (int rep = 0; rep < 3; ++rep) {
                run(h1d, h2d, h1l, h2l, false);
                run(Cone<double>(r1, h1), h2d, Cone<L>(r1, h1), h2l, false);
            }
        }
    }
    INFO(cases << " cases; " << overlapping << " placed at g ≤ −1e-6, " << fired << " decided by containment; boxes "
               << box_fired << " of " << box_overlaps << "; plain loop wrong at |g| ≥ 1e-9: " << corrected
               << " corrected by the certificate, " << both_wrong << " not");
    CHECK(cases > 0);
    CHECK(fired_not_overlapping == 0);
    CHECK(certified_wrong == 0);
    // The plain loop itself is right wherever long double decides (it answered "separated" for 5 of these pairs,
    // overlapping by 1e-9 of their size, before its plane-less exits were certified: test_gjk_certified_separation).
    CHECK(plain_wrong == 0);
    CHECK(both_wrong == 0);
    CHECK(differ == 0);
    CHECK(fired >= overlapping / 5);
    CHECK(box_fired >= box_overlaps / 2);
}

TEST_CASE("containment certificate agrees with the plain loop on random overlapping pairs", "[gjk][containment]") {
    // Random poses over ±0.15 with shapes of size ~0.1: a mix of clear, shallow and deep overlaps and of
    // separated pairs; every answer (status) with the certificate must equal the plain loop's.
    std::mt19937_64 rng(703);
    std::uniform_real_distribution<double> u(0.5, 1.0), t(-0.15, 0.15);
    GjkSettings<double> off;
    off.containment_test = false;
    int n = 0, differ = 0, colliding = 0, fired = 0;
    auto run = [&](const auto& a, const auto& b) {
        const Transform<double> pa(test::random_rotation(rng), Vec3<double>(t(rng), t(rng), t(rng)));
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(t(rng), t(rng), t(rng)));
        const auto on = gjk_intersect(a, pa, b, pb);
        const auto plain = gjk_intersect(a, pa, b, pb, nullptr, off);
        ++n;
        differ += on.status != plain.status;
        colliding += plain.colliding;
        fired += on.iterations >= 1 && on.status == GjkStatus::intersecting && on.simplex.size == 0;
    };
    for (int k = 0; k < test::scaled(3000, 300); ++k) {
        const double r1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h1 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        run(Box<double>(Vec3<double>(r1, h1, r2)), Cone<double>(r2, h2));
        run(Cylinder<double>(r1, h1), Box<double>(Vec3<double>(h2, r2, r1)));
        run(Cone<double>(r1, h1), Cylinder<double>(r2, h2));
        run(Capsule<double>(r1 / 2, h1), Box<double>(Vec3<double>(h2, r2, r1)));
        if (k % 10 == 0) {
            std::vector<Vec3<double>> cloud;
            for (int i = 0; i < 60; ++i) cloud.push_back(random_unit(rng) * 0.1 * u(rng));
            const ConvexPolyhedron<double> hull(cloud);
            for (int j = 0; j < 10; ++j) {
                run(hull, Box<double>(Vec3<double>(h2, r2, r1)));
                run(Cone<double>(r1, h1), hull);
                run(hull, hull);
            }
        }
    }
    INFO(n << " pairs, " << colliding << " colliding, " << fired << " decided by containment");
    CHECK(differ == 0);
    CHECK(colliding > n / 10);
    CHECK(fired > 0);
}
