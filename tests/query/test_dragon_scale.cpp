// collide() and distance() at scale: the Stanford dragon at 203k and 871k triangles (scripts/fetch-data, which
// scripts/test runs; a missing file fails the test) against itself at P2-style poses, judged by a reference that
// shares no code with the trees: a uniform grid over the triangles' boxes, every candidate pair tested.
//  - collide, ContactMode::all: the set of intersecting triangle pairs equals the grid's exactly (both run the
//    exact-predicate triangle test on the same rounded points of B in A's frame; that test is judged against CGAL
//    in tests/narrowphase); ContactMode::first reports one of those pairs.
//  - distance: equals the grid's minimum over every pair whose boxes lie within the answer, measured with this
//    file's own point–triangle and segment–segment distances (not cdkit's triangle_distance).
// Poses: a random rotation R and direction u, bisection along u to first contact, then B pushed in or pulled out
// by a fraction of the bounding-box diagonal (BENCHMARKS.md P2).
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

using namespace cdkit;

// Named: the unity build compiles this file with others of tests/query whose helpers share names.
namespace dragon_scale {

using V = Vec3<double>;
using Pairs = std::vector<std::pair<Index, Index>>;

struct Box {
    V lo, hi;
};
Box box_of(const V& a, const V& b, const V& c) { return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)}; }
bool boxes_within(const Box& a, const Box& b, double d) {
    return (a.lo.array() <= b.hi.array() + d).all() && (b.lo.array() <= a.hi.array() + d).all();
}

// Runs body(i) for i in [0, n) on every core; body must be thread-safe.
template <class F> void parallel_for(std::size_t n, F body) {
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&] {
            for (std::size_t i; (i = next.fetch_add(256)) < n;)
                for (std::size_t j = i; j < std::min(n, i + 256); ++j) body(j);
        });
    for (auto& th : pool) th.join();
}

// Triangles of A (its own frame) and of B carried into A's frame the way the queries carry them.
struct PosedPair {
    std::vector<std::array<V, 3>> ta, tb;
    std::vector<Box> ba, bb;
};
PosedPair posed(const TriangleMesh<double>& m, const Transform<double>& pa, const Transform<double>& pb) {
    const Transform<double> b_to_a = pa.inverse() * pb;
    PosedPair p;
    p.ta.resize(m.num_triangles()), p.tb.resize(m.num_triangles());
    p.ba.resize(m.num_triangles()), p.bb.resize(m.num_triangles());
    parallel_for(m.num_triangles(), [&](std::size_t i) {
        const auto& t = m.triangles[i];
        for (int k = 0; k < 3; ++k) {
            p.ta[i][k] = m.vertices[t[k]];
            p.tb[i][k] = detail::to_frame_a(b_to_a, m.vertices[t[k]]);
        }
        p.ba[i] = box_of(p.ta[i][0], p.ta[i][1], p.ta[i][2]);
        p.bb[i] = box_of(p.tb[i][0], p.tb[i][1], p.tb[i][2]);
    });
    return p;
}

// Every pair (i of A, j of B) whose boxes lie within `reach` of each other, through a uniform grid over the
// region both sets can meet in; `visit(i, j)` is called once per such pair, from several threads.
template <class Visit> void grid_pairs(const PosedPair& p, double reach, Visit visit) {
    Box all_a{V::Constant(1e300), V::Constant(-1e300)}, all_b = all_a;
    for (const Box& b : p.ba) all_a = {all_a.lo.cwiseMin(b.lo), all_a.hi.cwiseMax(b.hi)};
    for (const Box& b : p.bb) all_b = {all_b.lo.cwiseMin(b.lo), all_b.hi.cwiseMax(b.hi)};
    const Box region{all_a.lo.cwiseMax(all_b.lo - V::Constant(reach)), all_a.hi.cwiseMin(all_b.hi + V::Constant(reach))};
    if (!(region.lo.array() <= region.hi.array()).all()) return;
    std::vector<Index> in_a, in_b;
    for (Index i = 0; i < Index(p.ba.size()); ++i)
        if (boxes_within(p.ba[i], region, reach)) in_a.push_back(i);
    for (Index j = 0; j < Index(p.bb.size()); ++j)
        if (boxes_within(p.bb[j], region, reach)) in_b.push_back(j);
    if (in_a.empty() || in_b.empty()) return;
    // Cells about as many as B's candidates, at least the reach wide (so a pair within reach shares a cell of
    // B's grown box and A's box).
    const V ext = (region.hi - region.lo).cwiseMax(V::Constant(1e-12));
    const double cell = std::max(reach, std::cbrt(ext.prod() / double(in_b.size())));
    const Eigen::Array3i dims = ((ext / cell).array().floor().cast<int>() + 1).min(1024);
    auto cell_of = [&](const V& x) {
        return ((x - region.lo).array() / cell).floor().cast<int>().max(0).min(dims - 1).eval();
    };
    auto flat = [&](int x, int y, int z) { return (std::size_t(z) * dims.y() + y) * dims.x() + x; };
    std::vector<std::vector<Index>> cells(std::size_t(dims.prod()));
    for (Index j : in_b) {
        const auto lo = cell_of(p.bb[j].lo - V::Constant(reach)), hi = cell_of(p.bb[j].hi + V::Constant(reach));
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) cells[flat(x, y, z)].push_back(j);
    }
    parallel_for(in_a.size(), [&](std::size_t k) {
        const Index i = in_a[k];
        const auto lo = cell_of(p.ba[i].lo), hi = cell_of(p.ba[i].hi);
        std::vector<Index> seen;
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x)
                    for (Index j : cells[flat(x, y, z)]) seen.push_back(j);
        std::sort(seen.begin(), seen.end());
        seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
        for (Index j : seen)
            if (boxes_within(p.ba[i], p.bb[j], reach)) visit(i, j);
    });
}

Pairs grid_intersecting_pairs(const PosedPair& p) {
    Pairs out;
    std::mutex m;
    grid_pairs(p, 0.0, [&](Index i, Index j) {
        const auto& a = p.ta[i];
        const auto& b = p.tb[j];
        if (!triangles_intersect(a[0], a[1], a[2], b[0], b[1], b[2])) return;
        const std::lock_guard<std::mutex> lock(m);
        out.emplace_back(i, j);
    });
    std::sort(out.begin(), out.end());
    return out;
}

double point_segment(const V& x, const V& a, const V& b) {
    const V d = b - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0 ? std::clamp((x - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (a + t * d - x).norm();
}
double point_triangle(const V& x, const std::array<V, 3>& t) {
    double best = std::min({point_segment(x, t[0], t[1]), point_segment(x, t[1], t[2]), point_segment(x, t[2], t[0])});
    const V n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double nn = n.squaredNorm();
    if (nn > 0) {
        const V q = x - n * (n.dot(x - t[0]) / nn);
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && n.dot((t[(k + 1) % 3] - t[k]).cross(q - t[k])) >= 0;
        if (inside) best = std::min(best, (x - q).norm());
    }
    return best;
}
// Segments pq and rs: the unconstrained closest pair when it lies inside both, else an endpoint case.
double segment_segment(const V& p, const V& q, const V& r, const V& s) {
    double best = std::min({point_segment(p, r, s), point_segment(q, r, s), point_segment(r, p, q), point_segment(s, p, q)});
    const V d1 = q - p, d2 = s - r, w = p - r;
    const double a = d1.dot(d1), b = d1.dot(d2), c = d2.dot(d2), d = d1.dot(w), e = d2.dot(w);
    const double den = a * c - b * b;
    if (den > 1e-14 * a * c) {
        const double u = (b * e - c * d) / den, v = (a * e - b * d) / den;
        if (u > 0 && u < 1 && v > 0 && v < 1) best = std::min(best, (p + u * d1 - (r + v * d2)).norm());
    }
    return best;
}
// Distance of two disjoint triangles: a vertex against the other triangle, or two edges.
double triangle_gap(const std::array<V, 3>& a, const std::array<V, 3>& b) {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) best = std::min({best, point_triangle(a[k], b), point_triangle(b[k], a)});
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) best = std::min(best, segment_segment(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
    return best;
}

double grid_distance(const PosedPair& p, double within) {
    std::mutex m;
    double best = std::numeric_limits<double>::infinity();
    grid_pairs(p, within, [&](Index i, Index j) {
        const double g = triangle_gap(p.ta[i], p.tb[j]);
        const std::lock_guard<std::mutex> lock(m);
        best = std::min(best, g);
    });
    return best;
}

const TriangleMesh<double>& dragon(const char* file) {
    static std::map<std::string, TriangleMesh<double>> cache;
    auto it = cache.find(file);
    if (it == cache.end()) {
        const std::string path = test::data_path(file);
        INFO(path << " is missing: scripts/fetch-data downloads it (scripts/test runs it)");
        REQUIRE(std::filesystem::exists(path));
        it = cache.emplace(file, load_mesh(path)).first;
    }
    return it->second;
}

void check_dragon(const char* file, int poses, std::uint64_t seed) {
    const TriangleMesh<double>& mesh = dragon(file);
    const auto shared = std::make_shared<const TriangleMesh<double>>(mesh);
    const MeshModel<Obb<double>> obb(shared);
    const MeshModel<Rss<double>> rss(shared);
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double diag = (hi - lo).norm();
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> uni(-1, 1);
    CollisionRequest all;
    all.mode = ContactMode::all;
    int pairs_total = 0;
    for (int i = 0; i < poses; ++i) {
        const Transform<double> pa(test::random_rotation(rng), diag * V(uni(rng), uni(rng), uni(rng)));
        const Mat3<double> R = test::random_rotation(rng);
        V u(g(rng), g(rng), g(rng));
        u.normalize();
        auto pose_b = [&](double s) { return Transform<double>(pa.R * R, pa.t + s * u); };
        double in = 0, out = 2 * diag;
        for (int it = 0; it < 24; ++it) {
            const double mid = (in + out) / 2;
            (collide(obb, pa, obb, pose_b(mid)).colliding ? in : out) = mid;
        }
        for (const double delta : {-0.02, -0.002, 0.002, 0.02}) {
            const Transform<double> pb = pose_b((delta < 0 ? in : out) + delta * diag);
            INFO(file << " pose " << i << " δ = " << delta);
            const PosedPair p = posed(mesh, pa, pb);
            if (delta < 0) {
                const Pairs ref = grid_intersecting_pairs(p);
                const auto got = collide(obb, pa, obb, pb, all);
                INFO("cdkit " << got.contacts.size() << " pairs, grid " << ref.size());
                CHECK(test::contact_pairs(got) == ref);
                // Pushed in past first contact, B can still clear a thin part of A (a horn, a whisker): no pairs.
                const auto first = collide(rss, pa, rss, pb);
                REQUIRE(first.colliding == !ref.empty());
                if (first.colliding)
                    CHECK(std::binary_search(ref.begin(), ref.end(),
                                         std::pair(first.contacts[0].triangle_a, first.contacts[0].triangle_b)));
                pairs_total += int(ref.size());
            } else {
                const auto got = distance(rss, pa, rss, pb);
                REQUIRE(got.distance > 0);
                const double ref = grid_distance(p, double(got.distance) * (1 + 1e-9) + 1e-12 * diag);
                CHECK(std::abs(ref - double(got.distance)) <= 1e-10 * diag);
                CHECK(triangle_gap(p.ta[got.triangle_a], p.tb[got.triangle_b]) <= double(got.distance) + 1e-10 * diag);
                // the obb tree finds the same distance
                CHECK(std::abs(double(distance(obb, pa, obb, pb).distance) - ref) <= 1e-10 * diag);
            }
        }
    }
    WARN(file << ": " << poses << " poses, " << pairs_total << " intersecting pairs judged by the grid");
    CHECK(pairs_total > 0);
}

}  // namespace dragon_scale

TEST_CASE("collide and distance on the 203k dragon against a uniform-grid reference", "[query][dragon]") {
    dragon_scale::check_dragon("dragon/dragon_203k.ply", test::scaled(4, 1), 11);
}

TEST_CASE("collide and distance on the 871k dragon against a uniform-grid reference", "[query][dragon]") {
    dragon_scale::check_dragon("dragon/dragon_871k.ply", test::scaled(2, 1), 12);
}
