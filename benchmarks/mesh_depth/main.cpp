// cdkit_bench_mesh_depth: penetration depth of two intersecting copies of a closed mesh (the bunny, the Armadillo),
// scaled into [-1, 1]^3, at P2 poses (BENCHMARKS.md): per seeded random rotation of B and direction u, bisection to
// the touching translation s* along u, then B at (s* + δ·r)·u, r the bounding-sphere radius, δ ∈ {−0.01, −0.05, −0.2}.
//
// Methods, each warm and timed as the fastest of 3 batches of thread CPU time:
//   surface          penetration_depth(a, pa, b, pb): the intersection curve's normal, the directional depth along it
//   surface_refine1  the same with refine_steps = 1: 32 directions spread over the sphere, then tilts by 0.5 rad
//   surface_refine4  refine_steps = 4: tilts down to 0.0625 rad (each direction abandoned once it is no better)
//   ist              penetration_depth with both inner sphere trees: the penalty-force direction and the surface normal
//   ist_force_only   directional_depth along the inner sphere trees' penalty force alone (the force's own depth)
//   fcl_contacts     FCL 0.7 collide with enable_contact on OBBRSS trees: the largest penetration_depth over its
//                    triangle-pair contacts (FCL's depth for meshes)
// Reference: the sampled minimum translation — for 200 directions spread over the sphere and every method's own
// normal, the first translation of B along it at which FCL's collide() says the surfaces no longer cross (march in
// steps of 0.002·r, bisect to 1e-6·r), the minimum over them. Its error: the step (a gap shorter than a step is
// stepped over) and the sampling (the true minimum over all directions is at most this). Error = depth / reference − 1
// (median signed, p90 and max of |error|); vs_samples: the median against the 200 sampled directions alone.
//
// Force continuity: B moves along u from δ = +0.05 to δ = −0.2 in K steps (K = 25 … 400); the largest change of
// the inner sphere trees' penalty force between neighbouring steps over the largest force on the path, and the
// same for the `ist` depth. A continuous force halves its largest jump when K doubles.
//
// Usage: cdkit_bench_mesh_depth [--poses N] [--spheres N] [--mesh PATH]... [--csv FILE] [--force-csv FILE]
#include "../bench_util.hpp"
#include "../convex/batch_timer.hpp"
#include "../provenance.hpp"
#include "mesh_factory.hpp"
#include "oracles/fcl_mesh.hpp"
#include "oracles/sampled_translation.hpp"

#include <cdkit/io/load_mesh.hpp>
#include <cdkit/ist/inner_sphere_tree.hpp>
#include <cdkit/mesh_depth/penetration_depth.hpp>

#include <fcl/narrowphase/collision.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
using Model = cdkit::MeshModel<cdkit::Obb<double>>;
using cdbench::quantile;


double sample_ns(auto&& f) {
    double best = 1e300;
    for (int b = 0; b < 3; ++b) best = std::min(best, cdkit::bench::time_ns(f, 1));
    return best;
}

struct Object {
    std::string name;
    cdkit::TriangleMesh<double> mesh;
    std::unique_ptr<Model> model;
    std::unique_ptr<cdkit::InnerSphereTree> ist;
    std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model;
    double radius = 0;
};

/// The touching translation along u (B rotated by R), by bisection with cdkit's collide().
double touching(const Object& o, const cdkit::Mat3<double>& R, const V& u) {
    const T pa;
    T pb;
    pb.R = R;
    double lo = 0, hi = 4 * o.radius;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        pb.t = mid * u;
        (cdkit::collide(*o.model, pa, *o.model, pb).colliding ? lo : hi) = mid;
    }
    return hi;
}

struct Method {
    std::string name;
    std::vector<double> errors, sample_errors, ns;
    int colliding = 0, missing = 0;
};

}  // namespace

int main(int argc, char** argv) try {
    int poses = 8, spheres = 5000;
    const char *csv = nullptr, *force_csv = nullptr;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--poses") && i + 1 < argc) poses = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--spheres") && i + 1 < argc) spheres = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--mesh") && i + 1 < argc) files.emplace_back(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else if (!std::strcmp(argv[i], "--force-csv") && i + 1 < argc) force_csv = argv[++i];
        else throw std::runtime_error(std::string("unknown argument ") + argv[i]);
    }
    if (files.empty()) files = {CDKIT_SOURCE_DIR "/data/bunny.obj", CDKIT_SOURCE_DIR "/data/armadillo.obj"};

    std::FILE* out = csv ? std::fopen(csv, "w") : nullptr;
    std::FILE* fout = force_csv ? std::fopen(force_csv, "w") : nullptr;
    if ((csv && !out) || (force_csv && !fout)) throw std::runtime_error("cannot write the CSV files");
    if (out) {
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "mesh,delta,method,poses,colliding,median_error,p90_error,max_error,median_error_vs_samples,median_us\n");
    }
    if (fout) {
        cdbench::write_provenance(fout, argc, argv);
        std::fprintf(fout, "mesh,steps,max_force_jump,max_depth_jump\n");
    }
    std::printf("%-10s %6s %-16s %5s %5s %10s %10s %10s %10s %10s\n", "mesh", "delta", "method", "poses", "coll",
                "med_err", "p90_err", "max_err", "vs_samples", "med_us");

    const auto dirs = cdkit::test::sphere_directions(200);
    for (const std::string& file : files) {
        Object o;
        o.mesh = cdkit::test::unit_scaled(cdkit::load_mesh(file));
        o.name = std::filesystem::path(file).stem().string();
        for (const V& v : o.mesh.vertices) o.radius = std::max(o.radius, v.norm());
        o.model = std::make_unique<Model>(o.mesh);
        cdkit::PackingOptions packing;
        packing.max_spheres = std::size_t(spheres);
        o.ist = std::make_unique<cdkit::InnerSphereTree>(cdkit::build_inner_sphere_tree(o.mesh, packing));
        o.fcl_model = cdkit::test::fcl_mesh<fcl::OBBRSSd>(o.mesh);
        const T pa;
        fcl::CollisionObjectd fa(o.fcl_model, cdkit::test::fcl_pose(pa));

        for (const double delta : {-0.01, -0.05, -0.2}) {
            std::mt19937_64 rng(1000 + std::uint64_t(-delta * 1000));
            std::vector<Method> methods{{"surface"},        {"surface_refine1"}, {"surface_refine4"},
                                        {"ist"},            {"ist_force_only"},  {"fcl_contacts"}};
            for (int k = 0; k < poses; ++k) {
                const cdkit::Mat3<double> R = cdbench::random_rotation(rng);
                std::normal_distribution<double> g;
                const V u = V(g(rng), g(rng), g(rng)).normalized();
                T pb;
                pb.R = R;
                pb.t = (touching(o, R, u) + delta * o.radius) * u;
                fcl::CollisionObjectd fb(o.fcl_model, cdkit::test::fcl_pose(pb));

                cdkit::MeshDepthRequest refine, refine1;
                refine.refine_steps = 4;
                refine1.refine_steps = 1;
                std::vector<std::pair<double, V>> answers(methods.size(), {-1.0, V::Zero()});
                const auto keep = [&](std::size_t m, const cdkit::MeshDepthResult& r) {
                    if (r.colliding) answers[m] = {r.depth, r.normal};
                    return r.depth;
                };
                methods[0].ns.push_back(sample_ns([&] { return keep(0, cdkit::penetration_depth(*o.model, pa, *o.model, pb)); }));
                methods[1].ns.push_back(sample_ns([&] { return keep(1, cdkit::penetration_depth(*o.model, pa, *o.model, pb, refine1)); }));
                methods[2].ns.push_back(sample_ns([&] { return keep(2, cdkit::penetration_depth(*o.model, pa, *o.model, pb, refine)); }));
                methods[3].ns.push_back(sample_ns(
                    [&] { return keep(3, cdkit::penetration_depth(*o.model, *o.ist, pa, *o.model, *o.ist, pb)); }));
                methods[4].ns.push_back(sample_ns([&] {
                    const cdkit::PenetrationVolumeResult v = cdkit::penetration_volume(*o.ist, pa, *o.ist, pb);
                    const cdkit::PenaltyWrench w = cdkit::penalty_wrench(v, *o.ist, pa, *o.ist, pb, 1.0, pa.t, pb.t);
                    if (!(w.on_b.force.norm() > 0)) return 0.0;
                    return keep(4, cdkit::directional_depth(*o.model, pa, *o.model, pb, w.on_b.force));
                }));
                methods[5].ns.push_back(sample_ns([&] {
                    fcl::CollisionRequestd req(100000, true);
                    fcl::CollisionResultd res;
                    fcl::collide(&fa, &fb, req, res);
                    double deepest = -1;
                    V n = V::Zero();
                    for (std::size_t i = 0; i < res.numContacts(); ++i)
                        if (res.getContact(i).penetration_depth > deepest)
                            deepest = res.getContact(i).penetration_depth, n = res.getContact(i).normal;
                    if (deepest >= 0) answers[5] = {deepest, n};
                    return deepest;
                }));

                // The reference: FCL's boolean collide at translated poses.
                const auto crossing = [&](const V& v) {
                    T q = pb;
                    q.t += v;
                    fcl::CollisionObjectd fq(o.fcl_model, cdkit::test::fcl_pose(q));
                    fcl::CollisionRequestd req;
                    fcl::CollisionResultd res;
                    return fcl::collide(&fa, &fq, req, res) > 0;
                };
                const double sampled =
                    cdkit::test::sampled_min_translation(crossing, dirs, 0.002 * o.radius, 1e-6 * o.radius).depth;
                std::vector<V> own;
                for (const auto& [d, n] : answers)
                    if (d >= 0 && n.norm() > 0) own.push_back(n.normalized());
                const double ref = std::min(
                    sampled, cdkit::test::sampled_min_translation(crossing, own, 0.002 * o.radius, 1e-6 * o.radius).depth);
                for (std::size_t m = 0; m < methods.size(); ++m) {
                    if (answers[m].first < 0) {
                        ++methods[m].missing;
                        continue;
                    }
                    ++methods[m].colliding;
                    methods[m].errors.push_back(answers[m].first / ref - 1);
                    methods[m].sample_errors.push_back(answers[m].first / sampled - 1);
                }
            }
            for (const Method& m : methods) {
                std::vector<double> abs_err;
                for (double e : m.errors) abs_err.push_back(std::abs(e));
                const double med = quantile(m.errors, 0.5), p90 = quantile(abs_err, 0.9), mx = quantile(abs_err, 1.0);
                const double us = cdbench::median(m.ns) / 1000, vs = quantile(m.sample_errors, 0.5);
                std::printf("%-10s %6.2f %-16s %5d %5d %+10.4f %10.4f %10.4f %+10.4f %10.1f\n", o.name.c_str(), delta,
                            m.name.c_str(), poses, m.colliding, med, p90, mx, vs, us);
                if (out)
                    std::fprintf(out, "%s,%.2f,%s,%d,%d,%.4f,%.4f,%.4f,%.4f,%.1f\n", o.name.c_str(), delta, m.name.c_str(),
                                 poses, m.colliding, med, p90, mx, vs, us);
            }
        }

        // Force continuity along a path through the contact.
        std::mt19937_64 rng(77);
        const cdkit::Mat3<double> R = cdbench::random_rotation(rng);
        std::normal_distribution<double> g;
        const V u = V(g(rng), g(rng), g(rng)).normalized();
        const double s = touching(o, R, u);
        for (const int steps : {25, 50, 100, 200, 400}) {
            double fmax = 0, jump = 0, djump = 0;
            V last = V::Zero();
            double last_depth = 0;
            for (int i = 0; i <= steps; ++i) {
                T pb;
                pb.R = R;
                pb.t = (s + (0.05 - 0.25 * i / steps) * o.radius) * u;
                const cdkit::PenetrationVolumeResult v = cdkit::penetration_volume(*o.ist, pa, *o.ist, pb);
                const V f = cdkit::penalty_wrench(v, *o.ist, pa, *o.ist, pb, 1.0, pa.t, pb.t).on_b.force;
                const double depth = cdkit::penetration_depth(*o.model, *o.ist, pa, *o.model, *o.ist, pb).depth;
                fmax = std::max(fmax, f.norm());
                if (i > 0) jump = std::max(jump, (f - last).norm()), djump = std::max(djump, std::abs(depth - last_depth));
                last = f;
                last_depth = depth;
            }
            std::printf("%-10s force path, %3d steps: largest force jump %.4f of the largest force, depth jump %.4f·r\n",
                        o.name.c_str(), steps, jump / fmax, djump / o.radius);
            if (fout) std::fprintf(fout, "%s,%d,%.5f,%.5f\n", o.name.c_str(), steps, jump / fmax, djump / o.radius);
        }
    }
    if (out) std::fclose(out);
    if (fout) std::fclose(fout);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_mesh_depth: %s\n", e.what());
    return 1;
}
