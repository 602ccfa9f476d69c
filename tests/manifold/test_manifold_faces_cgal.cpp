// Face-on-face manifolds against the exact intersection polygon of the two faces (CGAL's Boolean set operations on
// the exact kernel, from the faces' double corners). A box or a hexagonal prism lies on a ground box at seeded
// random offsets, turns and sizes: every manifold point must be a vertex of the exact polygon (within rounding), all
// of them when the polygon has at most four, and four spanning at least half its area when it has more.
#include "cdkit/manifold/contact_manifold.hpp"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <catch2/catch.hpp>

#include <numbers>
#include <random>

using namespace cdkit;

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Polygon = CGAL::Polygon_2<K>;
using V = Vec3<double>;
using T = Transform<double>;

/// The exact intersection of two convex polygons given by their double corners (counter-clockwise).
std::vector<K::Point_2> exact_intersection(const std::vector<V>& a, const std::vector<V>& b) {
    Polygon pa, pb;
    for (const V& p : a) pa.push_back(K::Point_2(p.x(), p.y()));
    for (const V& p : b) pb.push_back(K::Point_2(p.x(), p.y()));
    std::vector<CGAL::Polygon_with_holes_2<K>> out;
    CGAL::intersection(pa, pb, std::back_inserter(out));
    std::vector<K::Point_2> v;
    if (!out.empty())
        for (auto it = out.front().outer_boundary().vertices_begin(); it != out.front().outer_boundary().vertices_end(); ++it)
            v.push_back(*it);
    return v;
}

double area(const std::vector<V>& p) {  // of the convex hull of ≤ 4 points in the xy-plane, any order
    V c = V::Zero();
    for (const V& q : p) c += q / double(p.size());
    std::vector<V> s = p;
    std::sort(s.begin(), s.end(), [&](const V& a, const V& b) {
        return std::atan2(a.y() - c.y(), a.x() - c.x()) < std::atan2(b.y() - c.y(), b.x() - c.x());
    });
    double twice = 0;
    for (std::size_t i = 0; i < s.size(); ++i) twice += s[i].x() * s[(i + 1) % s.size()].y() - s[i].y() * s[(i + 1) % s.size()].x();
    return std::abs(twice) / 2;
}

}  // namespace

TEST_CASE("face-on-face manifold points are vertices of the exact intersection polygon", "[manifold][cgal]") {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> u(0, 1);
    int cases = 0, more_than_four = 0;
    double worst_area_ratio = 1;
    for (int trial = 0; trial < 400; ++trial) {
        // The ground's top face: a rectangle at z = 0 (exact corners).
        const V g(0.3 + u(rng), 0.3 + u(rng), 0.5);
        const Box<double> ground(g);
        const T ground_pose = T::translation(V(0, 0, -0.5));
        const std::vector<V> top{V(-g.x(), -g.y(), 0), V(g.x(), -g.y(), 0), V(g.x(), g.y(), 0), V(-g.x(), g.y(), 0)};
        // The upper shape's bottom face, posed: a box's rectangle or a prism's hexagon.
        const bool prism = trial % 2 == 1;
        const double depth = 0.001 + 0.02 * u(rng);
        const double yaw = 2 * std::numbers::pi * u(rng);
        std::vector<V> local_bottom;
        double half_height;
        std::optional<Box<double>> box;
        std::optional<ConvexPolyhedron<double>> hull;
        if (prism) {
            const double r = 0.2 + u(rng);
            half_height = 0.25;
            std::vector<V> pts;
            for (int k = 0; k < 6; ++k) {
                const double a = k * std::numbers::pi / 3;
                pts.emplace_back(r * std::cos(a), r * std::sin(a), -half_height);
                pts.emplace_back(r * std::cos(a), r * std::sin(a), half_height);
                local_bottom.emplace_back(r * std::cos(a), r * std::sin(a), -half_height);
            }
            hull.emplace(pts);
        } else {
            const V h(0.2 + u(rng), 0.2 + u(rng), 0.3);
            half_height = h.z();
            box.emplace(h);
            local_bottom = {V(-h.x(), -h.y(), -h.z()), V(h.x(), -h.y(), -h.z()), V(h.x(), h.y(), -h.z()), V(-h.x(), h.y(), -h.z())};
        }
        const T pose(Eigen::AngleAxisd(yaw, V::UnitZ()).toRotationMatrix(),
                     V(2 * (u(rng) - 0.5) * g.x(), 2 * (u(rng) - 0.5) * g.y(), half_height - depth));
        std::vector<V> bottom;
        for (const V& p : local_bottom) bottom.push_back(pose * p);
        const std::vector<K::Point_2> exact = exact_intersection(top, bottom);
        if (exact.size() < 3) continue;  // the centre offset put the shape off the edge: no face contact
        const ContactManifold<double> m = prism ? contact_manifold(ground, ground_pose, *hull, pose)
                                                : contact_manifold(ground, ground_pose, *box, pose);
        ++cases;
        INFO("trial " << trial << (prism ? " prism" : " box") << ", exact polygon of " << exact.size() << " corners");
        REQUIRE(m.count >= 1);
        CHECK((m.normal - V::UnitZ()).norm() < 1e-12);
        std::vector<V> chosen;
        for (int i = 0; i < m.count; ++i) {
            const V& q = m.points[i].point_b;
            CHECK(m.points[i].depth == Approx(depth).margin(1e-12));
            double nearest = 1e300;
            for (const K::Point_2& e : exact)
                nearest = std::min(nearest, std::hypot(CGAL::to_double(e.x()) - q.x(), CGAL::to_double(e.y()) - q.y()));
            CHECK(nearest < 1e-12);
            chosen.push_back(q);
        }
        if (exact.size() <= 4) {
            CHECK(m.count == int(exact.size()));
        } else {
            ++more_than_four;
            CHECK(m.count == 4);
            std::vector<V> all;
            for (const K::Point_2& e : exact) all.emplace_back(CGAL::to_double(e.x()), CGAL::to_double(e.y()), 0);
            double exact_area = 0;  // the exact polygon is convex and in order
            for (std::size_t i = 0; i < all.size(); ++i)
                exact_area += all[i].x() * all[(i + 1) % all.size()].y() - all[i].y() * all[(i + 1) % all.size()].x();
            exact_area = std::abs(exact_area) / 2;
            const double ratio = area(chosen) / exact_area;
            worst_area_ratio = std::min(worst_area_ratio, ratio);
            CHECK(ratio > 0.5);
        }
    }
    INFO("cases " << cases << ", polygons of more than four corners " << more_than_four << ", worst area kept "
                  << worst_area_ratio);
    CHECK(cases > 250);
    CHECK(more_than_four > 50);
}
