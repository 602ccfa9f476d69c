// cdkit_bench_manifold: what a contact manifold costs, and against FCL. Four scenes of 200 seeded poses each, the
// shapes overlapping by 0.001–0.02: a box resting on a ground box (yaw any, tilt < 0.05 rad: face contacts), two
// boxes in random orientations, a hexagonal-prism hull resting on the ground, a cylinder standing on it. Methods,
// interleaved per pose, each warm (one untimed call) and timed as the fastest of 3 batches (batch_timer.hpp):
// cdkit contact_manifold (up to four points; two boxes take the separating-axis path), for the box scenes the same
// manifold with the boxes given as 8-corner hulls (the general GJK + EPA path: the axis test off), cdkit with
// ManifoldRequest::single_point (GJK and EPA, no features: what the manifold adds), FCL 0.7 collide with enable_contact and num_max_contacts = 4 (box–box: FCL's
// box–box routine with up to four contacts; the others: GJK/EPA, one contact). Every pose's boolean is compared.
// Usage: cdkit_bench_manifold [--poses N] [--csv FILE]
#include "../fcl_pose.hpp"
#include "../bench_util.hpp"
#include "../convex/batch_timer.hpp"
#include "../provenance.hpp"

#include <cdkit/manifold/contact_manifold.hpp>

#include <fcl/narrowphase/collision.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

double sample_ns(auto&& f) {
    double best = 1e300;
    for (int b = 0; b < 3; ++b) best = std::min(best, cdkit::bench::time_ns(f, 8));
    return best;
}

using cdbench::to_fcl;

struct Scene {
    std::string name;
    std::vector<T> pose_a, pose_b;
};

T tilted(std::mt19937_64& rng, double max_tilt, const V& t) {
    std::uniform_real_distribution<double> u(-1, 1);
    const Eigen::AngleAxisd yaw(std::numbers::pi * u(rng), V::UnitZ());
    const Eigen::AngleAxisd tilt(max_tilt * std::abs(u(rng)), V(u(rng), u(rng), 0).normalized());
    return {(tilt * yaw).toRotationMatrix(), t};
}

/// Moves B along `dir` until it just touches A (bisection on cdkit's boolean), then `overlap` further in.
template <class A, class B> T place_touching(const A& a, const T& pa, const B& b, T pb, const V& dir, double overlap) {
    double lo = 0, hi = 4;  // lo: overlapping, hi: apart
    for (int i = 0; i < 60; ++i) {
        const double mid = (lo + hi) / 2;
        T p = pb;
        p.t += mid * dir;
        (cdkit::gjk_intersect(a, pa, b, p).colliding ? lo : hi) = mid;
    }
    pb.t += (lo - overlap) * dir;
    return pb;
}

}  // namespace

int main(int argc, char** argv) try {
    int poses = 200;
    const char* csv = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--poses") && i + 1 < argc) poses = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else throw std::runtime_error(std::string("unknown argument ") + argv[i]);
    }
    const cdkit::Box<double> ground(V(5, 5, 0.5)), box(V(0.5, 0.4, 0.3));
    std::vector<V> prism;
    for (int k = 0; k < 6; ++k) {
        const double a = k * std::numbers::pi / 3;
        for (double z : {-0.25, 0.25}) prism.emplace_back(0.5 * std::cos(a), 0.5 * std::sin(a), z);
    }
    const cdkit::ConvexPolyhedron<double> hull(prism);
    const cdkit::Cylinder<double> cylinder(0.4, 0.5);
    const T ground_pose = T::translation(V(0, 0, -0.5));

    auto fcl_ground = std::make_shared<fcl::Boxd>(10, 10, 1);
    auto fcl_box = std::make_shared<fcl::Boxd>(1.0, 0.8, 0.6);
    auto fcl_cyl = std::make_shared<fcl::Cylinderd>(0.4, 1.0);
    auto verts = std::make_shared<std::vector<fcl::Vector3d>>(hull.vertices().begin(), hull.vertices().end());
    auto faces = std::make_shared<std::vector<int>>();
    int nfaces = 0;
    for (std::uint32_t f = 0; f < hull.face_count(); ++f, ++nfaces) {
        const auto loop = hull.face_vertices(f);
        faces->push_back(int(loop.size()));
        for (std::uint32_t v : loop) faces->push_back(int(v));
    }
    auto fcl_hull = std::make_shared<fcl::Convexd>(verts, nfaces, faces);

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    struct Row {
        std::string scene;
        std::vector<double> manifold, general, single, fcl, points, fcl_contacts;
        int disagreements = 0;
    };
    std::vector<Row> rows;
    const auto box_hull = [](const cdkit::Box<double>& b) {
        std::vector<V> c;
        for (double x : {-1.0, 1.0})
            for (double y : {-1.0, 1.0})
                for (double z : {-1.0, 1.0}) c.push_back(b.half.cwiseProduct(V(x, y, z)));
        return cdkit::ConvexPolyhedron<double>(c);
    };
    const cdkit::ConvexPolyhedron<double> ground_hull = box_hull(ground), box_as_hull = box_hull(box);
    auto run = [&](const std::string& name, const auto& a, const T& pa_fixed, bool random_a, const auto& b,
                   const std::shared_ptr<fcl::CollisionGeometryd>& ga, const std::shared_ptr<fcl::CollisionGeometryd>& gb,
                   bool resting, const cdkit::ConvexPolyhedron<double>* hull_a = nullptr,
                   const cdkit::ConvexPolyhedron<double>* hull_b = nullptr) {
        Row row{name};
        for (int i = 0; i < poses; ++i) {
            const T pa = random_a ? T(cdbench::random_rotation(rng), V::Zero()) : pa_fixed;
            T pb;
            V dir;
            if (resting) {
                pb = tilted(rng, 0.05, V(4 * (u(rng) - 0.5), 4 * (u(rng) - 0.5), 0));
                dir = V::UnitZ();
            } else {
                pb = T(cdbench::random_rotation(rng), V::Zero());
                std::normal_distribution<double> g;
                dir = V(g(rng), g(rng), g(rng)).normalized();
            }
            pb = place_touching(a, pa, b, pb, dir, 0.001 + 0.019 * u(rng));
            cdkit::ManifoldRequest single;
            single.single_point = true;
            const cdkit::ContactManifold<double> m = cdkit::contact_manifold(a, pa, b, pb);
            fcl::CollisionObjectd oa(ga, to_fcl(pa)), ob(gb, to_fcl(pb));
            fcl::CollisionRequestd req(4, true);
            fcl::CollisionResultd res;
            fcl::collide(&oa, &ob, req, res);
            row.disagreements += m.colliding != res.isCollision();
            row.points.push_back(m.count);
            row.fcl_contacts.push_back(double(res.numContacts()));
            row.manifold.push_back(sample_ns([&] { return cdkit::contact_manifold(a, pa, b, pb).count; }));
            if (hull_a && hull_b)
                row.general.push_back(sample_ns([&] { return cdkit::contact_manifold(*hull_a, pa, *hull_b, pb).count; }));
            row.single.push_back(sample_ns([&] { return cdkit::contact_manifold(a, pa, b, pb, single).count; }));
            row.fcl.push_back(sample_ns([&] {
                fcl::CollisionResultd r;
                fcl::collide(&oa, &ob, req, r);
                return int(r.numContacts());
            }));
        }
        rows.push_back(std::move(row));
    };
    run("box_on_ground", ground, ground_pose, false, box, fcl_ground, fcl_box, true, &ground_hull, &box_as_hull);
    run("box_box_random", box, T{}, true, box, fcl_box, fcl_box, false, &box_as_hull, &box_as_hull);
    run("hull_on_ground", ground, ground_pose, false, hull, fcl_ground, fcl_hull, true);
    run("cylinder_on_ground", ground, ground_pose, false, cylinder, fcl_ground, fcl_cyl, true);

    std::FILE* out = csv ? std::fopen(csv, "w") : nullptr;
    if (csv && !out) throw std::runtime_error(std::string("cannot write ") + csv);
    if (out) {
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "scene,poses,cdkit_points,fcl_contacts,cdkit_manifold_ns,cdkit_as_hulls_ns,cdkit_single_point_ns,"
                          "fcl_ns,ratio,disagreements\n");
    }
    std::printf("%-20s %6s %7s %7s %12s %12s %14s %10s %7s %6s\n", "scene", "poses", "points", "fcl_pts", "manifold_ns",
                "as_hulls_ns", "single_pt_ns", "fcl_ns", "fcl/cd", "disagr");
    int disagreements = 0;
    for (const Row& r : rows) {
        const double mf = cdbench::median(r.manifold), sp = cdbench::median(r.single), fc = cdbench::median(r.fcl);
        const std::string gen = r.general.empty() ? "" : std::to_string(int(std::lround(cdbench::median(r.general))));
        std::printf("%-20s %6d %7.0f %7.0f %12.0f %12s %14.0f %10.0f %7.2f %6d\n", r.scene.c_str(), poses,
                    cdbench::median(r.points), cdbench::median(r.fcl_contacts), mf, gen.c_str(), sp, fc, fc / mf,
                    r.disagreements);
        if (out)
            std::fprintf(out, "%s,%d,%.0f,%.0f,%.0f,%s,%.0f,%.0f,%.2f,%d\n", r.scene.c_str(), poses,
                         cdbench::median(r.points), cdbench::median(r.fcl_contacts), mf, gen.c_str(), sp, fc, fc / mf,
                         r.disagreements);
        disagreements += r.disagreements;
    }
    if (out) std::fclose(out);
    return disagreements == 0 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_manifold: %s\n", e.what());
    return 1;
}
