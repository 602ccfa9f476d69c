// cdkit_bench_mesh_convex: robot-link shapes against environment meshes, cdkit's mesh–convex collide() and
// distance() against FCL 0.7 (BVHModel<OBBRSSd> with the matching fcl primitive) in one process, on the same poses.
//
//   cdkit_bench_mesh_convex [--rotations N] [--seed S] [--csv FILE] MESH...
//
// Meshes are scaled into [-1, 1]³ about their box centre. Shapes (sizes in those units): a sphere (r 0.1), a
// capsule (r 0.05, length 0.3), a box (0.2 × 0.12 × 0.3) and a convex hull of 120 points on an ellipsoid (0.3 ×
// 0.18 × 0.24), all `fcl::Convex` in FCL (cdkit's hull triangles). Poses, P2-style (BENCHMARKS.md): for each of N
// random rotations and directions u the shape's centre walks in along u from outside until cdkit first reports
// contact, bisection finds the touching offset s*, and the queries run at s* + δ·r, r the mesh's bounding radius
// (1 here): δ ∈ {−0.01 (overlapping), 0, +0.001 (near contact), +0.01, +0.05, +0.2 (distant)}.
// Queries: boolean collide (cdkit MeshModel<Obb>, no witness point; FCL's default request: one contact, no contact
// data) and, for δ > 0, distance (cdkit MeshModel<Rss>; FCL's default distance request). FCL gets both of its GJK
// solvers (libccd, the default, and its own "indep"); the faster one's median is the peer (column fcl_solver).
// Timing (docs/benchmarks.md, "Warm batches"): per pose and method one untimed call, then 3 batches of ≥ 20 µs of
// thread CPU time (benchmarks/convex/batch_timer.hpp), the fastest batch's mean is the pose's sample; the methods
// run pose by pose in turn; medians over the poses of a class. ratio = FCL median / cdkit median (> 1: cdkit faster).
// Answers compared on every pose: a boolean that differs from FCL's (either solver) counts as a disagreement,
// unless cdkit's distance at that pose is within 1e-6 of touching (FCL's GJK tolerance): then it is "undecided"
// and counted apart. A distance that differs by more than 1e-5 + 1e-4·d is a difference too. Each difference
// beyond the band goes to a third, exact opinion (the smallest triangle_distance between the mesh's and the
// shape's triangles, a sphere being a point and a capsule a segment plus the radius): where it confirms cdkit the
// row's fcl_wrong counts it, otherwise disagreements does. Exit status 1 on any disagreement.
#include "../fcl_pose.hpp"
#include "../bench_util.hpp"
#include "../convex/batch_timer.hpp"
#include "../provenance.hpp"

#include <cdkit/io/load_mesh.hpp>
#include <cdkit/mesh_convex.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/triangle_distance.hpp>

#include <fcl/fcl.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

using cdbench::random_rotation;
using cdbench::median;

using cdbench::to_fcl;


/// Fastest of 3 warm batches, µs per call.
template <class F> double sample_us(F&& f) {
    double best = 1e300;
    for (int b = 0; b < 3; ++b) best = std::min(best, cdkit::bench::time_ns(f, 8));
    return best / 1000;
}

volatile double g_sink = 0;

/// The shape as triangles (local frame) grown by a margin, for the independent reference: a sphere is a point, a
/// capsule a segment (degenerate triangles), a box its 12 faces' triangles, a hull its triangles.
struct ShapeTriangles {
    std::vector<std::array<V, 3>> tris;
    double margin = 0;
};

/// Third opinion where cdkit and FCL differ: the smallest exact triangle–triangle distance (triangle_distance:
/// Ericson's 15 feature pairs plus the exact intersection test) between the mesh and the shape's triangles, minus
/// the margin. The mesh triangles farther than `reach` from the shape's bounding ball are skipped. (For a solid
/// shape this is its surface's distance: the same as the solid's wherever the two are apart.)
double reference_distance(const cdkit::TriangleMesh<double>& mesh, const T& pose, const ShapeTriangles& st, double reach) {
    std::vector<std::array<V, 3>> placed;
    V c = V::Zero();
    for (const auto& t : st.tris) {
        placed.push_back({pose * t[0], pose * t[1], pose * t[2]});
        c += placed.back()[0] + placed.back()[1] + placed.back()[2];
    }
    c /= double(3 * placed.size());
    double R = 0;
    for (const auto& t : placed)
        for (const auto& v : t) R = std::max(R, (v - c).norm());
    double best = 1e300;
    for (const auto& tri : mesh.triangles) {
        const V &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &d = mesh.vertices[tri[2]];
        const V m = (a + b + d) / 3.0;
        const double rt = std::max({(a - m).norm(), (b - m).norm(), (d - m).norm()});
        if ((m - c).norm() - rt - R - st.margin > reach) continue;
        for (const auto& t : placed)
            best = std::min(best, cdkit::triangle_distance(a, b, d, t[0], t[1], t[2]).distance);
    }
    return std::max(best - st.margin, 0.0);
}

struct Row {
    std::string mesh, shape, query;
    std::size_t triangles = 0;
    double delta = 0;
    std::vector<double> cdkit_us, ccd_us, indep_us, bv_tests, tri_tests;
    int colliding = 0, disagreements = 0, undecided = 0, fcl_wrong = 0;
};

const char* delta_class(double d) {
    if (d < 0) return "overlapping";
    if (d <= 0.001) return "near";
    if (d <= 0.05) return "close";
    return "distant";
}

template <class C>
void run_shape(const std::string& mesh_name, const cdkit::MeshModel<cdkit::Obb<double>>& obb,
               const cdkit::MeshModel<cdkit::Rss<double>>& rss, const std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>& fmesh,
               const std::string& shape_name, const C& shape, const std::shared_ptr<fcl::CollisionGeometryd>& fshape,
               const ShapeTriangles& st, int rotations, std::uint64_t seed, std::vector<Row>& rows) {
    const double deltas[] = {-0.01, 0.0, 0.001, 0.01, 0.05, 0.2};
    std::vector<Row> local;
    for (const char* q : {"collide", "distance"})
        for (double d : deltas) {
            if (std::string(q) == "distance" && d <= 0) continue;
            Row r;
            r.mesh = mesh_name, r.shape = shape_name, r.query = q, r.triangles = obb.mesh().triangles.size(), r.delta = d;
            local.push_back(r);
        }
    auto row = [&](const char* q, double d) -> Row& {
        for (auto& r : local)
            if (r.query == q && r.delta == d) return r;
        return local.front();
    };
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    fcl::CollisionRequestd creq_ccd, creq_indep;
    creq_indep.gjk_solver_type = fcl::GST_INDEP;
    fcl::DistanceRequestd dreq_ccd, dreq_indep;
    dreq_indep.gjk_solver_type = fcl::GST_INDEP;
    cdkit::MeshConvexRequest boolean;
    boolean.witness_points = false;
    const T id;
    for (int k = 0; k < rotations; ++k) {
        const cdkit::Mat3<double> R = random_rotation(rng);
        const V u = V(g(rng), g(rng), g(rng)).normalized();
        auto at = [&](double s) { return T(R, s * u); };
        auto hits = [&](double s) { return cdkit::collide(obb, id, shape, at(s), boolean).colliding; };
        double lo = -1, hi = 3;
        for (double s = 3; s >= 0; s -= 0.02)
            if (hits(s)) {
                lo = s, hi = s + 0.02;
                break;
            }
        if (lo < 0) continue;  // the shape never touches a triangle along u (cannot happen from outside)
        for (int it = 0; it < 50; ++it) ((hits(0.5 * (lo + hi))) ? lo : hi) = 0.5 * (lo + hi);
        for (double d : deltas) {
            const T p = at(lo + d);
            const fcl::Transform3d fp = to_fcl(p);
            const fcl::Transform3d fid = fcl::Transform3d::Identity();
            {
                Row& r = row("collide", d);
                const auto res = cdkit::collide(obb, id, shape, p, boolean);
                r.colliding += res.colliding;
                r.bv_tests.push_back(double(res.stats.bv_tests));
                r.tri_tests.push_back(double(res.stats.primitive_tests));
                fcl::CollisionResultd a, b;
                fcl::collide(fmesh.get(), fid, fshape.get(), fp, creq_ccd, a);
                fcl::collide(fmesh.get(), fid, fshape.get(), fp, creq_indep, b);
                if (a.isCollision() != res.colliding || b.isCollision() != res.colliding) {
                    const double dist = cdkit::distance(rss, id, shape, p).distance;
                    if (dist <= 1e-6) ++r.undecided;
                    else {
                        // Beyond the band: the exact triangle reference decides who is wrong.
                        const double ref = reference_distance(obb.mesh(), p, st, dist + 1e-3);
                        const bool ref_hit = ref <= 1e-9;
                        if (ref_hit == res.colliding) ++r.fcl_wrong;
                        else ++r.disagreements;
                        std::printf("%s %s %s delta %g rotation %d: cdkit %d, fcl libccd %d, fcl indep %d, cdkit "
                                    "distance %.3g, reference %.3g\n",
                                    ref_hit == res.colliding ? "FCL WRONG" : "DISAGREEMENT", mesh_name.c_str(),
                                    shape_name.c_str(), d, k, int(res.colliding), int(a.isCollision()),
                                    int(b.isCollision()), dist, ref);
                    }
                }
                r.cdkit_us.push_back(sample_us([&] { g_sink = g_sink + cdkit::collide(obb, id, shape, p, boolean).colliding; }));
                r.ccd_us.push_back(sample_us([&] {
                    fcl::CollisionResultd x;
                    fcl::collide(fmesh.get(), fid, fshape.get(), fp, creq_ccd, x);
                    g_sink = g_sink + x.isCollision();
                }));
                r.indep_us.push_back(sample_us([&] {
                    fcl::CollisionResultd x;
                    fcl::collide(fmesh.get(), fid, fshape.get(), fp, creq_indep, x);
                    g_sink = g_sink + x.isCollision();
                }));
            }
            if (d > 0) {
                Row& r = row("distance", d);
                const auto res = cdkit::distance(rss, id, shape, p);
                r.colliding += res.colliding;
                r.bv_tests.push_back(double(res.stats.bv_tests));
                r.tri_tests.push_back(double(res.stats.primitive_tests));
                fcl::DistanceResultd a, b;
                fcl::distance(fmesh.get(), fid, fshape.get(), fp, dreq_ccd, a);
                fcl::distance(fmesh.get(), fid, fshape.get(), fp, dreq_indep, b);
                // Distances: FCL's GJK converges to 1e-6; beyond that band the answers must agree.
                for (double fd : {a.min_distance, b.min_distance})
                    if (std::abs(fd - res.distance) > 1e-5 + 1e-4 * res.distance) {
                        // The exact triangle reference decides: cdkit must equal it (to 1e-9), else it is wrong.
                        const double ref = reference_distance(obb.mesh(), p, st, std::max(fd, res.distance) + 1e-3);
                        const bool cdkit_right = std::abs(ref - res.distance) <= 1e-9 * std::max(1.0, ref);
                        if (cdkit_right) ++r.fcl_wrong;
                        else ++r.disagreements;
                        std::printf("%s %s %s distance delta %g rotation %d: cdkit %.9g, fcl %.9g, reference %.9g\n",
                                    cdkit_right ? "FCL WRONG" : "DISAGREEMENT", mesh_name.c_str(), shape_name.c_str(),
                                    d, k, res.distance, fd, ref);
                        break;
                    }
                r.cdkit_us.push_back(sample_us([&] { g_sink = g_sink + cdkit::distance(rss, id, shape, p).distance; }));
                r.ccd_us.push_back(sample_us([&] {
                    fcl::DistanceResultd x;
                    fcl::distance(fmesh.get(), fid, fshape.get(), fp, dreq_ccd, x);
                    g_sink = g_sink + x.min_distance;
                }));
                r.indep_us.push_back(sample_us([&] {
                    fcl::DistanceResultd x;
                    fcl::distance(fmesh.get(), fid, fshape.get(), fp, dreq_indep, x);
                    g_sink = g_sink + x.min_distance;
                }));
            }
        }
    }
    rows.insert(rows.end(), local.begin(), local.end());
}

}  // namespace

int main(int argc, char** argv) try {
    int rotations = 30;
    std::uint64_t seed = 1;
    std::string csv;
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--rotations" && i + 1 < argc) rotations = std::stoi(argv[++i]);
        else if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
        else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
        else meshes.push_back(a);
    }
    if (meshes.empty()) meshes.push_back(CDKIT_SOURCE_DIR "/data/bunny.obj");

    // The shapes: robot-link sizes in the meshes' [-1, 1]³ units.
    const cdkit::Sphere<double> sphere(0.1);
    const cdkit::Capsule<double> capsule(0.05, 0.15);
    const cdkit::Box<double> box(V(0.1, 0.06, 0.15));
    std::mt19937_64 hull_rng(seed + 100);
    std::normal_distribution<double> hg;
    std::vector<V> pts;
    for (int i = 0; i < 120; ++i) pts.push_back(V(hg(hull_rng), hg(hull_rng), hg(hull_rng)).normalized().cwiseProduct(V(0.15, 0.09, 0.12)));
    const cdkit::ConvexPolyhedron<double> hull(pts);
    auto hv = std::make_shared<std::vector<fcl::Vector3d>>(hull.vertices().begin(), hull.vertices().end());
    auto hf = std::make_shared<std::vector<int>>();
    for (const auto& t : hull.triangles()) hf->insert(hf->end(), {3, int(t[0]), int(t[1]), int(t[2])});
    const auto f_sphere = std::make_shared<fcl::Sphered>(0.1);
    const auto f_capsule = std::make_shared<fcl::Capsuled>(0.05, 0.3);
    const auto f_box = std::make_shared<fcl::Boxd>(0.2, 0.12, 0.3);
    const auto f_hull = std::make_shared<fcl::Convexd>(hv, int(hull.triangles().size()), hf);
    for (auto* s : std::initializer_list<fcl::CollisionGeometryd*>{f_sphere.get(), f_capsule.get(), f_box.get(), f_hull.get()})
        s->computeLocalAABB();
    std::printf("hull: %zu vertices, %zu triangles\n", hull.vertices().size(), hull.triangles().size());
    ShapeTriangles st_sphere{{{V::Zero(), V::Zero(), V::Zero()}}, 0.1};
    ShapeTriangles st_capsule{{{V(0, 0, -0.15), V(0, 0, 0.15), V(0, 0, 0.15)}}, 0.05};
    ShapeTriangles st_box, st_hull;
    {
        auto corner = [&](int i) { return V(i & 1 ? 0.1 : -0.1, i & 2 ? 0.06 : -0.06, i & 4 ? 0.15 : -0.15); };
        const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
        for (const auto& f : faces) {
            st_box.tris.push_back({corner(f[0]), corner(f[1]), corner(f[2])});
            st_box.tris.push_back({corner(f[0]), corner(f[2]), corner(f[3])});
        }
        for (const auto& t : hull.triangles())
            st_hull.tris.push_back({hull.vertices()[t[0]], hull.vertices()[t[1]], hull.vertices()[t[2]]});
    }

    std::vector<Row> rows;
    for (const auto& path : meshes) {
        cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(path);
        V lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const double scale = 2.0 / (hi - lo).maxCoeff();
        for (auto& v : mesh.vertices) v = (v - 0.5 * (lo + hi)) * scale;
        const std::string name = path.substr(path.find_last_of('/') + 1);
        const auto shared = std::make_shared<const cdkit::TriangleMesh<double>>(std::move(mesh));
        const cdkit::MeshModel<cdkit::Obb<double>> obb(shared);
        const cdkit::MeshModel<cdkit::Rss<double>> rss(shared);
        std::vector<fcl::Vector3d> verts(shared->vertices.begin(), shared->vertices.end());
        std::vector<fcl::Triangle> tris;
        for (const auto& t : shared->triangles) tris.emplace_back(t[0], t[1], t[2]);
        auto fmesh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
        fmesh->beginModel(int(tris.size()), int(verts.size()));
        fmesh->addSubModel(verts, tris);
        fmesh->endModel();
        fmesh->computeLocalAABB();
        std::printf("%s: %zu triangles\n", name.c_str(), tris.size());
        std::fflush(stdout);
        run_shape(name, obb, rss, fmesh, "sphere", sphere, f_sphere, st_sphere, rotations, seed, rows);
        run_shape(name, obb, rss, fmesh, "capsule", capsule, f_capsule, st_capsule, rotations, seed + 1, rows);
        run_shape(name, obb, rss, fmesh, "box", box, f_box, st_box, rotations, seed + 2, rows);
        run_shape(name, obb, rss, fmesh, "hull", hull, f_hull, st_hull, rotations, seed + 3, rows);
    }

    std::FILE* out = csv.empty() ? nullptr : std::fopen(csv.c_str(), "w");
    if (out) {
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "mesh,triangles,shape,query,delta,class,poses,colliding,cdkit_median_us,fcl_median_us,"
                          "fcl_solver,ratio,fcl_libccd_median_us,fcl_indep_median_us,cdkit_bv_tests,cdkit_tri_tests,"
                          "disagreements,undecided,fcl_wrong\n");
    }
    std::printf("\n%-16s %-8s %-8s %7s %5s %5s %10s %10s %-6s %7s %9s %9s %6s %5s %6s\n", "mesh", "shape", "query",
                "delta", "poses", "coll", "cdkit_us", "fcl_us", "solver", "ratio", "bv_tests", "tri_tests", "disagr",
                "undec", "fclbad");
    int disagreements = 0, undecided = 0, fcl_wrong = 0;
    for (const auto& r : rows) {
        const double c = median(r.cdkit_us), a = median(r.ccd_us), b = median(r.indep_us);
        const double f = std::min(a, b);
        const char* solver = a <= b ? "libccd" : "indep";
        const double ratio = c > 0 ? f / c : 0;
        disagreements += r.disagreements;
        undecided += r.undecided;
        fcl_wrong += r.fcl_wrong;
        std::printf("%-16s %-8s %-8s %7.3f %5zu %5d %10.2f %10.2f %-6s %7.2f %9.0f %9.0f %6d %5d %6d\n", r.mesh.c_str(),
                    r.shape.c_str(), r.query.c_str(), r.delta, r.cdkit_us.size(), r.colliding, c, f, solver, ratio,
                    median(r.bv_tests), median(r.tri_tests), r.disagreements, r.undecided, r.fcl_wrong);
        if (out)
            std::fprintf(out, "%s,%zu,%s,%s,%g,%s,%zu,%d,%.3f,%.3f,%s,%.2f,%.3f,%.3f,%.0f,%.0f,%d,%d,%d\n", r.mesh.c_str(),
                         r.triangles, r.shape.c_str(), r.query.c_str(), r.delta, delta_class(r.delta), r.cdkit_us.size(),
                         r.colliding, c, f, solver, ratio, a, b, median(r.bv_tests), median(r.tri_tests),
                         r.disagreements, r.undecided, r.fcl_wrong);
    }
    if (out) std::fclose(out);
    std::printf("\ncdkit answers the exact triangle reference contradicts (disagreements): %d; boolean differences within "
                "1e-6 of touching (undecided): %d; FCL answers the reference contradicts: %d\n",
                disagreements, undecided, fcl_wrong);
    return disagreements == 0 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_mesh_convex: %s\n", e.what());
    return 2;
}
