// cdkit_bench_mesh_ccd: continuous collision of two rigid copies of a mesh, cdkit's mesh_ccd on its trees against
// FCL 0.7's fcl::continuousCollide with conservative advancement on BVHModel<RSS> (the BV its mesh CA works with;
// OBBRSS is printed too), in one process on the same motions.
//
//   cdkit_bench_mesh_ccd [--trials N] [--seed S] [--brute-force-max T] [--brute-force-trials K] [--csv FILE] MESH...
//
// Each mesh is scaled into [-1, 1]³ about its box centre. B stays at the origin under a random rotation; A starts
// 3.5 away along a random direction u under a random rotation and ends 3.5 away on the other side, offset
// sideways by up to 1.5 (so it passes through B, grazes it, or passes by). Two classes of motion:
//   translation  A keeps its rotation: the two libraries move the vertices alike (linearly), so their times of
//                contact are compared, and misses are counted against a reference independent of both CCDs: a
//                contact is certain when FCL's discrete collide finds the meshes overlapping at t = 0.1, …, 0.9;
//   rotation     A also turns 90° about a random axis during the step. cdkit moves each vertex on its chord
//                between the two poses, FCL (CCDM_LINEAR) along the rotation's arc: the times differ by design,
//                only the speed and how often each reports contact are printed.
// On meshes of at most T triangles (default 4000) the first K motions of each class (default 5) are also run by
// all-pairs primitive CCD (mesh_ccd_brute_force, no tree): mesh_ccd must agree on contact and on the earliest time.
// Per class and method: median / max ms per query (each query warm: one untimed run, then the fastest of 3),
// contacts reported, FCL CA RSS's median over the row's (the speed-up), for translation the largest
// |toi_cdkit − toi_fcl| over pairs both call colliding, and the certain contacts the method missed.
#include "../fcl_pose.hpp"
#include "../bench_util.hpp"
#include "../provenance.hpp"
#include <cdkit/bv/obb.hpp>
#include <cdkit/bv/rss.hpp>
#include <cdkit/ccd/mesh_ccd.hpp>
#include <cdkit/io/load_mesh.hpp>

#include <fcl/fcl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

using cdbench::random_rotation;
using cdbench::median;

using cdbench::to_fcl;


}  // namespace

int main(int argc, char** argv) try {
    int trials = 40;
    std::size_t fcl_iterations = 10;  // FCL's default
    std::size_t brute_force_max = 4000;  // triangles up to which all-pairs primitive CCD checks the motions
    int brute_force_trials = 5;          // how many motions of each class it checks (about 10 s each on the bunny)
    std::uint64_t seed = 1;
    std::string csv;
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--trials" && i + 1 < argc) trials = std::stoi(argv[++i]);
        else if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
        else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
        else if (a == "--fcl-iterations" && i + 1 < argc) fcl_iterations = std::stoul(argv[++i]);
        else if (a == "--brute-force-max" && i + 1 < argc) brute_force_max = std::stoul(argv[++i]);
        else if (a == "--brute-force-trials" && i + 1 < argc) brute_force_trials = std::stoi(argv[++i]);
        else meshes.push_back(a);
    }
    if (meshes.empty()) meshes.push_back(CDKIT_SOURCE_DIR "/data/bunny.obj");
    std::FILE* out = csv.empty() ? nullptr : std::fopen(csv.c_str(), "w");
    if (out) {
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "mesh,triangles,motion,method,queries,contacts,median_ms,max_ms,fcl_rss_over_this,"
                          "max_toi_difference,misses,all_pairs_motions,all_pairs_disagree,max_dtoi_all_pairs\n");
    }
    std::printf("%-14s %9s %-11s %-22s %7s %8s %10s %10s %8s %9s %6s\n", "mesh", "triangles", "motion", "method",
                "queries", "contacts", "median_ms", "max_ms", "RSS/x", "max|dtoi|", "misses");
    for (const auto& path : meshes) {
        cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(path);
        V lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const double scale = 2.0 / (hi - lo).maxCoeff();
        for (auto& v : mesh.vertices) v = (v - 0.5 * (lo + hi)) * scale;
        const std::string name = path.substr(path.find_last_of('/') + 1);
        const cdkit::MeshModel<cdkit::Obb<double>> obb(mesh);
        const cdkit::MeshModel<cdkit::Rss<double>> rss(mesh);
        std::vector<fcl::Vector3d> verts(mesh.vertices.begin(), mesh.vertices.end());
        std::vector<fcl::Triangle> tris;
        for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
        fcl::BVHModel<fcl::OBBRSSd> model;
        model.beginModel(int(tris.size()), int(verts.size()));
        model.addSubModel(verts, tris);
        model.endModel();
        // FCL's conservative advancement on meshes works with RSS only (fcl#120, fcl#555: OBBRSS's bounds are
        // summed with their signs); both are run, RSS is the peer the ratio divides by.
        fcl::BVHModel<fcl::RSSd> model_rss;
        model_rss.beginModel(int(tris.size()), int(verts.size()));
        model_rss.addSubModel(verts, tris);
        model_rss.endModel();

        for (const bool rotate : {false, true}) {
            std::mt19937_64 rng(seed);
            std::uniform_real_distribution<double> side(0, 1.5), angle(0, 2 * M_PI);
            std::vector<double> ms_obb, ms_rss, ms_fcl, ms_fcl_obbrss;
            int hits_obb = 0, hits_rss = 0, hits_fcl = 0, hits_fcl_obbrss = 0, misses = 0, misses_obbrss = 0;
            int cdkit_misses = 0, certain_contacts = 0, late_toi = 0, brute_checked = 0, brute_disagree = 0;
            double max_brute_dtoi = 0;
            double max_dtoi = 0;
            for (int k = 0; k < trials; ++k) {
                const V u = random_rotation(rng).col(0);
                const V w = u.unitOrthogonal();
                const V lateral = side(rng) * (Eigen::AngleAxisd(angle(rng), u) * w);
                const cdkit::Mat3<double> r0 = random_rotation(rng), rb = random_rotation(rng);
                const cdkit::Mat3<double> r1 =
                    rotate ? cdkit::Mat3<double>(Eigen::AngleAxisd(M_PI / 2, random_rotation(rng).col(0)) * r0) : r0;
                const T a0(r0, -3.5 * u + lateral), a1(r1, 3.5 * u + lateral), b(rb, V::Zero());
                cdkit::DeformableCcdResult ro, rr;
                ms_obb.push_back(1e3 * cdbench::warm_best_seconds([&] { ro = cdkit::mesh_ccd(obb, a0, a1, obb, b, b); }));
                ms_rss.push_back(1e3 * cdbench::warm_best_seconds([&] { rr = cdkit::mesh_ccd(rss, a0, a1, rss, b, b); }));
                fcl::ContinuousCollisionRequestd req;
                req.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
                req.ccd_motion_type = rotate ? fcl::CCDM_LINEAR : fcl::CCDM_TRANS;
                req.num_max_iterations = fcl_iterations;
                fcl::ContinuousCollisionResultd res, res_obbrss;
                // FCL's CCDM_LINEAR builds InterpMotion(tf1, tf2), which leaves its reference point uninitialised
                // (fcl#662): rotating motions are built here with the reference point at the origin.
                auto fcl_ccd = [&](const auto& geometry, fcl::ContinuousCollisionResultd& r) {
                    r = fcl::ContinuousCollisionResultd();
                    if (rotate) {
                        const fcl::InterpMotion<double> ma(a0.R, a0.t, a1.R, a1.t, V::Zero()),
                            mb(b.R, b.t, b.R, b.t, V::Zero());
                        fcl::continuousCollide<double>(&geometry, &ma, &geometry, &mb, req, r);
                    } else {
                        fcl::continuousCollide(&geometry, to_fcl(a0), to_fcl(a1), &geometry, to_fcl(b), to_fcl(b), req,
                                               r);
                    }
                };
                ms_fcl.push_back(1e3 * cdbench::warm_best_seconds([&] { fcl_ccd(model_rss, res); }));
                ms_fcl_obbrss.push_back(1e3 * cdbench::warm_best_seconds([&] { fcl_ccd(model, res_obbrss); }));
                // All-pairs primitive CCD over the same (chord) motion, on meshes small enough for it: mesh_ccd's
                // earliest time must equal it.
                if (mesh.triangles.size() <= brute_force_max && k < brute_force_trials) {
                    const cdkit::DeformableCcdResult all = cdkit::mesh_ccd_brute_force(mesh, a0, a1, mesh, b, b);
                    ++brute_checked;
                    brute_disagree += all.colliding != ro.colliding;
                    if (all.colliding && ro.colliding) max_brute_dtoi = std::max(max_brute_dtoi, std::abs(all.toi - ro.toi));
                }
                hits_fcl_obbrss += res_obbrss.is_collide;
                hits_obb += ro.colliding;
                hits_rss += rr.colliding;
                hits_fcl += res.is_collide;
                if (!rotate) {
                    // A contact certainly happens when FCL's discrete collide sees the meshes overlap at one of
                    // nine instants of the (straight) path: the reference both CCD answers are judged by.
                    // An overlap seen before cdkit's time of first contact would make that time too late.
                    bool certain = false;
                    for (int s = 1; s <= 9; ++s) {
                        const double t = s / 10.0;
                        fcl::CollisionRequestd creq;
                        fcl::CollisionResultd cres;
                        const T at(r0, (1 - t) * a0.t + t * a1.t);
                        const bool overlap = fcl::collide(&model, to_fcl(at), &model, to_fcl(b), creq, cres) > 0;
                        certain = certain || overlap;
                        late_toi += overlap && (!ro.colliding || t < ro.toi);
                    }
                    certain_contacts += certain;
                    misses += certain && !res.is_collide;
                    misses_obbrss += certain && !res_obbrss.is_collide;
                    cdkit_misses += certain && !(ro.colliding && rr.colliding);
                    if (ro.colliding && res.is_collide) max_dtoi = std::max(max_dtoi, std::abs(ro.toi - res.time_of_contact));
                }
            }
            const char* motion = rotate ? "rotation" : "translation";
            const double fcl_median = median(ms_fcl);
            auto row = [&](const char* method, const std::vector<double>& ms, int hits, int missed) {
                const double ratio = fcl_median / median(ms);  // FCL CA RSS's median over this row's
                const double dtoi = rotate ? 0.0 : max_dtoi;
                std::printf("%-14s %9zu %-11s %-22s %7d %8d %10.3f %10.3f %8.2f %9.2g %6d\n", name.c_str(),
                            mesh.triangles.size(), motion, method, trials, hits, median(ms),
                            *std::max_element(ms.begin(), ms.end()), ratio, dtoi, missed);
                // The all-pairs check is of mesh_ccd: FCL's rows leave its columns empty.
                char all_pairs[64] = ",,";
                if (std::string(method).rfind("cdkit", 0) == 0 && brute_checked > 0)
                    std::snprintf(all_pairs, sizeof all_pairs, "%d,%d,%.3g", brute_checked, brute_disagree,
                                  max_brute_dtoi);
                if (out)
                    std::fprintf(out, "%s,%zu,%s,%s,%d,%d,%.4f,%.4f,%.3f,%.3g,%d,%s\n", name.c_str(), mesh.triangles.size(),
                                 motion, method, trials, hits, median(ms), *std::max_element(ms.begin(), ms.end()), ratio,
                                 dtoi, missed, all_pairs);
            };
            if (!rotate)
                std::printf("%-14s %9zu %-11s contacts certain by FCL's discrete collide along the path: %d; overlaps "
                            "it saw before cdkit's first contact time: %d\n",
                            name.c_str(), mesh.triangles.size(), motion, certain_contacts, late_toi);
            if (brute_checked > 0)
                std::printf("%-14s %9zu %-11s all-pairs primitive CCD on %d motions: %d disagree on contact, largest "
                            "|toi - toi_all_pairs| %.3g\n",
                            name.c_str(), mesh.triangles.size(), motion, brute_checked, brute_disagree, max_brute_dtoi);
            row("cdkit mesh_ccd Obb", ms_obb, hits_obb, cdkit_misses);
            row("cdkit mesh_ccd Rss", ms_rss, hits_rss, cdkit_misses);
            row("FCL CA RSS", ms_fcl, hits_fcl, misses);
            row("FCL CA OBBRSS", ms_fcl_obbrss, hits_fcl_obbrss, misses_obbrss);
        }
    }
    if (out) std::fclose(out);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_mesh_ccd: %s\n", e.what());
    return 2;
}
