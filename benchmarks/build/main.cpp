/// \file cdkit_bench_build: protocol P5 of BENCHMARKS.md. For every BV type and build strategy over the mesh
/// ladder: build time (TBB-parallel where cdkit has TBB, and on one thread), bytes of the tree per triangle and
/// the ratio to the mesh's own bytes (the lecture's requirement: under 2×), refit time after a smooth
/// deformation and how much the refit loosened the tree, and the first-contact query time the tree gives on a
/// fixed set of near poses. FCL's BVHModel build and refit for its BV types in the same run.
///
/// Usage: cdkit_bench_build [--quick] [--mesh PATH]... [--reps N] [--poses N] [--csv FILE] [--no-fcl]
///   default meshes: data/bunny.obj and every data/dragon/dragon_*.ply present (scripts/fetch-data);
///   --quick: the bunny and dragon_48k only, fewer rows.

#include "../cli_args.hpp"
#include "../provenance.hpp"
#include "../thread_cpu_clock.hpp"
#include "peer_fcl.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/task_arena.h>
#endif

using namespace cdkit;

namespace {

// The parallel build is timed on the wall clock (its threads' CPU times would add up); everything
// single-threaded on the calling thread's CPU clock, like the FCL peer, so that a shared machine's load
// does not count.
using WallClock = std::chrono::steady_clock;
using CpuClock = cdbench::ThreadCpuClock;
using cdbench::ms_since;

struct Options {
    std::vector<std::string> meshes;
    bool quick = false;
    bool fcl = true;
    int reps = 3;
    int poses = 200;
    std::string csv = "build.csv";
};

Options parse(int argc, char** argv) {
    Options o;
    for (cdbench::ArgCursor args(argc, argv); args.next();) {
        const std::string a = args.flag();
        if (a == "--quick") o.quick = true;
        else if (a == "--mesh") o.meshes.push_back(args.value());
        else if (a == "--reps") o.reps = std::max(1, std::atoi(args.value().c_str()));
        else if (a == "--poses") o.poses = std::max(1, std::atoi(args.value().c_str()));
        else if (a == "--csv") o.csv = args.value();
        else if (a == "--no-fcl") o.fcl = false;
        else {
            std::fprintf(stderr, "usage: cdkit_bench_build [--quick] [--mesh PATH]... [--reps N] [--poses N] [--csv FILE] [--no-fcl]\n");
            std::exit(a == "--help" || a == "-h" ? 0 : 2);
        }
    }
    if (o.meshes.empty()) {
        const std::string root = CDKIT_BENCH_SOURCE_DIR;
        o.meshes.push_back(root + "/data/bunny.obj");
        for (const char* d : {"11k", "48k", "203k", "871k"}) {
            if (o.quick && std::string(d) != "48k") continue;
            const std::string p = root + "/data/dragon/dragon_" + std::string(d) + ".ply";
            if (std::filesystem::exists(p)) o.meshes.push_back(p);
        }
    }
    return o;
}

/// A smooth deformation: every vertex displaced by a sine field of amplitude 2% of the mesh's extent.
TriangleMesh<double> deformed(const TriangleMesh<double>& m) {
    Vec3<double> lo = m.vertices[0], hi = lo;
    for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double extent = (hi - lo).maxCoeff(), a = 0.02 * extent, k = 2 * 3.14159265358979 / extent;
    TriangleMesh<double> out = m;
    for (auto& v : out.vertices) v += a * Vec3<double>(std::sin(k * v.y()), std::sin(k * v.z()), std::sin(k * v.x()));
    return out;
}

/// Fixed near poses for the query column: B rotated at random and moved along a random direction by a
/// random fraction (0 … 0.6) of the mesh's extent, so that about half collide.
std::vector<Transform<double>> near_poses(const TriangleMesh<double>& m, int n) {
    Vec3<double> lo = m.vertices[0], hi = lo;
    for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double extent = (hi - lo).maxCoeff();
    const Vec3<double> c = (lo + hi) / 2;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0, 0.6);
    std::vector<Transform<double>> out;
    for (int i = 0; i < n; ++i) {
        Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
        q.normalize();
        Vec3<double> d(g(rng), g(rng), g(rng));
        d = d.normalized() * u(rng) * extent;
        const Mat3<double> R = q.toRotationMatrix();
        out.emplace_back(R, c - R * c + d);  // rotation about the centre, then the shift
    }
    return out;
}

struct Row {
    std::string mesh;
    std::size_t triangles = 0;
    std::string method, split;
    unsigned leaf = 1;
    double build_ms = 0, build_1t_ms = 0, refit_ms = 0, degradation = 0;
    std::size_t tree_bytes = 0, mesh_bytes = 0;
    double query_us = -1;  ///< median first-contact µs over the near poses (-1: not measured)
    int colliding = 0;
};

/// The degradation column: "–" where the tree has no volume measure (negative).
std::string degradation_text(const Row& r) {
    if (r.degradation < 0) return "–";
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", r.degradation);
    return b;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

const char* split_name(SplitStrategy s) {
    switch (s) {
    case SplitStrategy::median: return "median";
    case SplitStrategy::mean: return "mean";
    case SplitStrategy::sah: return "sah";
    case SplitStrategy::pca_volume: return "pca_volume";
    }
    return "?";
}

template <class M> TriangleMesh<M> as_scalar(const TriangleMesh<double>& m) {
    if constexpr (std::is_same_v<M, double>) return m;
    else return m.template cast<M>();
}

template <class Model, class M>
void measure_queries_and_refit(Model& model, const std::shared_ptr<const TriangleMesh<M>>& moved,
                               const std::vector<Transform<double>>& poses, Row& r);

/// One cdkit row: BV over a mesh of scalar M.
template <class BV, class M>
Row measure(const std::string& name, const std::string& method, const TriangleMesh<double>& mesh_d,
            const TriangleMesh<double>& moved_d, const std::vector<Transform<double>>& poses, SplitStrategy split,
            unsigned leaf, int reps) {
    const auto mesh = std::make_shared<const TriangleMesh<M>>(as_scalar<M>(mesh_d));
    const auto moved = std::make_shared<const TriangleMesh<M>>(as_scalar<M>(moved_d));
    Row r;
    r.mesh = name;
    r.triangles = mesh->triangles.size();
    r.method = method;
    r.split = split_name(split);
    r.leaf = leaf;
    BuildOptions opt;
    opt.split = split;
    opt.max_leaf_triangles = leaf;
    std::vector<double> t;
    std::unique_ptr<MeshModel<BV, M>> model;
    for (int i = 0; i < reps; ++i) {
        const auto t0 = WallClock::now();
        model = std::make_unique<MeshModel<BV, M>>(mesh, opt);  // validation + build: what a user pays
        t.push_back(ms_since<WallClock>(t0));
    }
    r.build_ms = median(t);
    BuildOptions one = opt;
    one.parallel = false;
    {
        const auto t0 = CpuClock::now();
        const MeshModel<BV, M> m1(mesh, one);
        r.build_1t_ms = ms_since<CpuClock>(t0);
    }
    measure_queries_and_refit(*model, moved, poses, r);
    r.degradation = model->degradation();
    return r;
}

/// The columns every tree shares: bytes, first-contact query time on the freshly built tree, then the refit
/// after the deformation (validation of the moved mesh included: refit() checks it).
template <class Model, class M>
void measure_queries_and_refit(Model& model, const std::shared_ptr<const TriangleMesh<M>>& moved,
                               const std::vector<Transform<double>>& poses, Row& r) {
    r.tree_bytes = model.memory_bytes();
    r.mesh_bytes = moved->vertices.size() * 3 * sizeof(M) + moved->triangles.size() * sizeof(Triangle);
    std::vector<double> us;
    for (const auto& p : poses) {
        const Transform<M> pb = p.template cast<M>();
        const auto t0 = CpuClock::now();
        const auto res = collide(model, Transform<M>(), model, pb);
        us.push_back(ms_since<CpuClock>(t0) * 1e3);
        r.colliding += res.colliding;
    }
    r.query_us = median(us);
    const auto t0 = CpuClock::now();
    model.refit(moved);
    r.refit_ms = ms_since<CpuClock>(t0);
}

/// A restricted boxtree row (bvh/boxtree.hpp): its own implied-SAH build, one triangle per leaf; wall clock
/// with its TBB-parallel subtrees, and thread CPU time in a one-thread arena.
template <class M>
Row measure_boxtree(const std::string& name, const TriangleMesh<double>& mesh_d, const TriangleMesh<double>& moved_d,
                    const std::vector<Transform<double>>& poses, int reps) {
    const auto mesh = std::make_shared<const TriangleMesh<M>>(as_scalar<M>(mesh_d));
    const auto moved = std::make_shared<const TriangleMesh<M>>(as_scalar<M>(moved_d));
    Row r;
    r.mesh = name;
    r.triangles = mesh->triangles.size();
    r.method = std::is_same_v<M, float> ? "boxtree_f" : "boxtree_d";
    r.split = "implied_sah";
    std::vector<double> t;
    std::unique_ptr<RestrictedBoxtree<M>> tree;
    for (int i = 0; i < reps; ++i) {
        const auto t0 = WallClock::now();
        tree = std::make_unique<RestrictedBoxtree<M>>(mesh);
        t.push_back(ms_since<WallClock>(t0));
    }
    r.build_ms = median(t);
    const auto one_thread = [&] {
        const auto t0 = CpuClock::now();
        const RestrictedBoxtree<M> serial(mesh);
        r.build_1t_ms = ms_since<CpuClock>(t0);
    };
#if defined(CDKIT_HAS_TBB)
    tbb::task_arena(1).execute(one_thread);
#else
    one_thread();
#endif
    measure_queries_and_refit(*tree, moved, poses, r);
    r.degradation = -1;  // no volume measure for implied boxes
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    std::printf("cdkit_bench_build (P5): %u hardware threads, cdkit %s TBB; reps %d (median), %d query poses\n",
                std::thread::hardware_concurrency(),
#if defined(CDKIT_HAS_TBB)
                "with",
#else
                "without",
#endif
                o.reps, o.poses);
    std::vector<Row> rows;
    struct FclRow {
        std::string mesh, kind;
        std::size_t triangles;
        cdbuild::FclTimes t;
        std::size_t mesh_bytes;
    };
    std::vector<FclRow> fcl_rows;
    for (const auto& path : o.meshes) {
        TriangleMesh<double> mesh;
        try {
            mesh = load_mesh(path);
        } catch (const Error& e) {
            std::fprintf(stderr, "skipping %s: %s\n", path.c_str(), e.what());
            continue;
        }
        const std::string name = std::filesystem::path(path).filename().string();
        const TriangleMesh<double> moved = deformed(mesh);
        const auto poses = near_poses(mesh, o.poses);
        const int reps = mesh.triangles.size() > 400000 ? 1 : o.reps;
        std::fprintf(stderr, "%s: %zu triangles\n", name.c_str(), mesh.triangles.size());
        const std::vector<SplitStrategy> splits = o.quick ? std::vector<SplitStrategy>{BuildOptions{}.split}
                                                          : std::vector<SplitStrategy>{SplitStrategy::median, SplitStrategy::sah,
                                                                                       SplitStrategy::pca_volume};
        for (SplitStrategy s : splits) {
            rows.push_back(measure<Obb<double>, double>(name, "obb_d", mesh, moved, poses, s, 1, reps));
            rows.push_back(measure<Aabb<double>, double>(name, "aabb_d", mesh, moved, poses, s, 1, reps));
            rows.push_back(measure<Obb<float>, double>(name, "obb_f/d", mesh, moved, poses, s, 1, reps));
            rows.push_back(measure<Aabb<float>, double>(name, "aabb_f/d", mesh, moved, poses, s, 1, reps));
            if (!o.quick) {
                rows.push_back(measure<Obb<float>, float>(name, "obb_f", mesh, moved, poses, s, 1, reps));
                rows.push_back(measure<Kdop<double, 14>, double>(name, "kdop14_d", mesh, moved, poses, s, 1, reps));
                rows.push_back(measure<Kdop<double, 18>, double>(name, "kdop18_d", mesh, moved, poses, s, 1, reps));
                rows.push_back(measure<Kdop<double, 26>, double>(name, "kdop26_d", mesh, moved, poses, s, 1, reps));
                rows.push_back(measure<BoundingSphere<double>, double>(name, "sphere_d", mesh, moved, poses, s, 1, reps));
            }
        }
        // Compact trees: float boxes with up to 4 triangles per leaf (the memory requirement, under 2× the mesh).
        rows.push_back(measure<Aabb<float>, double>(name, "aabb_f/d", mesh, moved, poses, BuildOptions{}.split, 4, reps));
        rows.push_back(measure<Obb<float>, double>(name, "obb_f/d", mesh, moved, poses, BuildOptions{}.split, 4, reps));
        rows.push_back(measure<Aabb<float>, float>(name, "aabb_f", mesh, moved, poses, BuildOptions{}.split, 4, reps));
        rows.push_back(measure<Obb<float>, float>(name, "obb_f", mesh, moved, poses, BuildOptions{}.split, 4, reps));
        rows.push_back(measure_boxtree<double>(name, mesh, moved, poses, reps));
        rows.push_back(measure_boxtree<float>(name, mesh, moved, poses, reps));
        if (o.fcl)
            for (const auto& kind : cdbuild::fcl_bv_kinds())
                fcl_rows.push_back({name, kind, mesh.triangles.size(), cdbuild::fcl_build_and_refit(kind, mesh, moved, reps),
                                    mesh.vertices.size() * 24 + mesh.triangles.size() * 12});
    }

    std::printf("\n| mesh | triangles | method | split | leaf | build ms | 1-thread ms | tree B/tri | tree/mesh | refit ms | "
                "degradation | query µs | colliding |\n|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Row& r : rows)
        std::printf("| %s | %zu | cdkit %s | %s | %u | %.1f | %.1f | %.1f | %.2f | %.1f | %s | %.1f | %d |\n", r.mesh.c_str(),
                    r.triangles, r.method.c_str(), r.split.c_str(), r.leaf, r.build_ms, r.build_1t_ms,
                    double(r.tree_bytes) / double(r.triangles), double(r.tree_bytes) / double(r.mesh_bytes), r.refit_ms,
                    degradation_text(r).c_str(), r.query_us, r.colliding);
    for (const FclRow& f : fcl_rows)
        std::printf("| %s | %zu | FCL %s | mean | 1 | %.1f | %.1f | ≥ %.1f | ≥ %.2f | %.1f | | | |\n", f.mesh.c_str(), f.triangles,
                    f.kind.c_str(), f.t.build_ms, f.t.build_ms, double(f.t.bv_bytes) / double(f.triangles),
                    double(f.t.bv_bytes) / double(f.mesh_bytes), f.t.refit_ms);
    std::printf("(method x_f/d: float BVs over the double mesh; build ms: MeshModel construction, validation included, "
                "median of reps, wall clock (TBB-parallel); 1-thread ms, refit, query and FCL: thread CPU time; tree/mesh: tree bytes over the mesh's vertex and index bytes in the mesh's scalar; "
                "degradation: MeshModel::degradation() after the refit (– for boxtrees: implied boxes have no volume measure here); boxtree: RestrictedBoxtree, its own build; query: first contact on %d fixed near poses; "
                "FCL bytes: its BV nodes only)\n", o.poses);
    // Provenance first (command, machine, compiler, commit, date), then the rows.
    if (std::FILE* head = std::fopen(o.csv.c_str(), "w")) {
        cdbench::write_provenance(head, argc, argv);
        std::fclose(head);
    }
    std::ofstream csv(o.csv, std::ios::app);
    csv << "mesh,triangles,library,method,split,leaf,build_ms,build_1thread_ms,tree_bytes,mesh_bytes,refit_ms,degradation,"
           "query_median_us,colliding\n";
    for (const Row& r : rows)
        csv << r.mesh << ',' << r.triangles << ",cdkit," << r.method << ',' << r.split << ',' << r.leaf << ',' << r.build_ms
            << ',' << r.build_1t_ms << ',' << r.tree_bytes << ',' << r.mesh_bytes << ',' << r.refit_ms << ',' << (r.degradation < 0 ? std::string() : std::to_string(r.degradation))
            << ',' << r.query_us << ',' << r.colliding << '\n';
    for (const FclRow& f : fcl_rows)
        csv << f.mesh << ',' << f.triangles << ",fcl," << f.kind << ",mean,1," << f.t.build_ms << ',' << f.t.build_ms << ','
            << f.t.bv_bytes << ',' << f.mesh_bytes << ',' << f.t.refit_ms << ",,,\n";
    std::printf("CSV: %s\n", o.csv.c_str());
    return 0;
}
