/// \file CGAL's exact kernel as the referee of the accuracy benchmark (the only TU that includes CGAL).

#include "oracles.hpp"
#include "oracles/cgal_simplex.hpp"

#include <algorithm>
#include <numeric>

namespace cdkit::accuracy {
namespace {

using test::cgal::Simplex;
using test::cgal::intersect;
using test::cgal::simplex;

}  // namespace

bool exact_triangles_intersect(const Tri3& p, const Tri3& q) { return intersect(simplex(p), simplex(q)); }

PairList exact_intersecting_pairs(const TriangleMesh<double>& a, const TriangleMesh<double>& b) {
    struct Box {
        Vec3<double> lo, hi;
    };
    auto boxes = [](const TriangleMesh<double>& m) {
        std::vector<Box> out;
        out.reserve(m.triangles.size());
        for (const auto& t : m.triangles) {
            const auto& v0 = m.vertices[t[0]];
            const auto& v1 = m.vertices[t[1]];
            const auto& v2 = m.vertices[t[2]];
            out.push_back({v0.cwiseMin(v1).cwiseMin(v2), v0.cwiseMax(v1).cwiseMax(v2)});  // min/max are exact
        }
        return out;
    };
    const std::vector<Box> ba = boxes(a), bb = boxes(b);
    // Sweep along x: B's triangles sorted by lo.x; for each A triangle scan those with lo.x <= its hi.x.
    std::vector<Index> order(bb.size());
    std::iota(order.begin(), order.end(), Index(0));
    std::sort(order.begin(), order.end(), [&](Index i, Index j) { return bb[i].lo.x() < bb[j].lo.x(); });
    std::vector<Simplex> sb(b.triangles.size());
    std::vector<char> have_sb(b.triangles.size(), 0);
    PairList out;
    for (Index i = 0; i < a.triangles.size(); ++i) {
        const Box& x = ba[i];
        const Simplex sa = simplex(a.triangle(i));
        for (Index j : order) {
            const Box& y = bb[j];
            if (y.lo.x() > x.hi.x()) break;
            if ((y.hi.array() < x.lo.array()).any() || (y.lo.array() > x.hi.array()).any()) continue;
            if (!have_sb[j]) sb[j] = simplex(b.triangle(j)), have_sb[j] = 1;
            if (intersect(sa, sb[j])) out.emplace_back(i, j);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace cdkit::accuracy
