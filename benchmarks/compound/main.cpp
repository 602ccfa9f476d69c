// cdkit_bench_compound: a concave object modelled as a compound of convex parts, against the mesh itself.
//
// Decomposition (fixed: computed at start from seeds, no data file): the bunny scaled into [-1, 1]³; the centres of
// a 40³ grid of voxels that lie inside it (exact winding numbers, ist/inside_test.hpp); k-means on them (k parts,
// seeded, 30 iterations); each part the convex hull of its voxels' corners. The parts are inner voxels grown by half a
// voxel, so the compound follows the solid to about a voxel (0.05 here), overfilling concave dents a little.
//
// Probes: a sphere (r 0.08), a box (half 0.06), a capsule (r 0.04, half length 0.08), at N seeded random poses near the
// surface (a random point of a random triangle moved by up to 0.25 in a random direction; random rotations). For each
// pose: collide_shapes of the probe against the mesh shape (a surface contact) and against the compound, and the
// solid's truth: the probe meets the bunny's volume iff it touches the surface or its centre is inside. Counted: agree
// (compound = solid); inside (the probe lies wholly inside: the mesh's surface contact misses it by design, the
// compound reports it); extra (compound touches, the solid does not) and missed (the solid touches, the compound does
// not), with the largest distance of an extra probe from the surface and the largest depth of a missed one below its
// deepest facet (the decomposition's error, to compare with the voxel). Times: collide_shapes per query, median over
// the poses of the fastest of 3 warm batches (thread CPU time), with the mesh's depth off and on
// (WorldOptions::mesh_depth).
//
// Usage: cdkit_bench_compound [--poses N] [--parts K] [--csv FILE]
#include "../bench_util.hpp"
#include "../convex/batch_timer.hpp"
#include "../provenance.hpp"
#include "mesh_factory.hpp"

#include <cdkit/io/load_mesh.hpp>
#include <cdkit/ist/inside_test.hpp>
#include <cdkit/mesh_convex.hpp>
#include <cdkit/world/narrow_phase.hpp>

#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
using Shape = cdkit::Shape<double>;

double sample_ns(auto&& f) {
    double best = 1e300;
    for (int b = 0; b < 3; ++b) best = std::min(best, cdkit::bench::time_ns(f, 4));
    return best;
}

/// The decomposition described above.
Shape decompose(const cdkit::TriangleMesh<double>& mesh, int grid, int parts, std::uint64_t seed, double& voxel) {
    const cdkit::InsideTest inside(mesh);
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    voxel = (hi - lo).maxCoeff() / grid;
    std::vector<V> centres;
    for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j)
            for (int k = 0; k < grid; ++k) {
                const V c = lo + voxel * V(i + 0.5, j + 0.5, k + 0.5);
                if (inside.inside(c)) centres.push_back(c);
            }
    std::mt19937_64 rng(seed);
    std::vector<V> means;
    for (int p = 0; p < parts; ++p) means.push_back(centres[std::uniform_int_distribution<std::size_t>(0, centres.size() - 1)(rng)]);
    std::vector<int> label(centres.size(), 0);
    for (int it = 0; it < 30; ++it) {
        for (std::size_t i = 0; i < centres.size(); ++i) {
            int best = 0;
            for (int p = 1; p < parts; ++p)
                if ((centres[i] - means[p]).squaredNorm() < (centres[i] - means[best]).squaredNorm()) best = p;
            label[i] = best;
        }
        std::vector<V> sum(parts, V::Zero());
        std::vector<int> count(parts, 0);
        for (std::size_t i = 0; i < centres.size(); ++i) sum[label[i]] += centres[i], ++count[label[i]];
        for (int p = 0; p < parts; ++p)
            if (count[p] > 0) means[p] = sum[p] / count[p];
    }
    std::vector<Shape> children;
    for (int p = 0; p < parts; ++p) {
        std::vector<V> corners;
        for (std::size_t i = 0; i < centres.size(); ++i)
            if (label[i] == p)
                for (int c = 0; c < 8; ++c)
                    corners.push_back(centres[i] + 0.5 * voxel * V(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1));
        if (corners.size() >= 8) children.push_back(Shape::convex_hull(corners));
    }
    return Shape::compound(std::move(children));
}

struct Row {
    std::string probe;
    int poses = 0, solid = 0, agree = 0, inside = 0, extra = 0, missed = 0;
    double max_extra_gap = 0, max_missed_depth = 0;
    std::vector<double> mesh_ns, mesh_depth_ns, compound_ns;
};

}  // namespace

int main(int argc, char** argv) try {
    int poses = 1000, parts = 24;
    const char* csv = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--poses") && i + 1 < argc) poses = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--parts") && i + 1 < argc) parts = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else throw std::runtime_error(std::string("unknown argument ") + argv[i]);
    }
    const cdkit::TriangleMesh<double> bunny = cdkit::test::unit_scaled(cdkit::load_mesh(CDKIT_SOURCE_DIR "/data/bunny.obj"));
    double voxel = 0;
    const Shape compound = decompose(bunny, 40, parts, 1, voxel);
    const Shape mesh = Shape::mesh(bunny);
    const cdkit::InsideTest inside(bunny);
    const cdkit::MeshModel<cdkit::Rss<double>> rss(bunny);
    std::printf("bunny: %zu triangles; compound of %zu convex parts (voxel %.3f)\n", bunny.triangles.size(),
                compound.compound_shape().children().size(), voxel);

    cdkit::ManifoldRequest depth_on, depth_off;
    depth_off.mesh_depth = false;
    std::vector<Row> rows;
    const std::vector<std::pair<std::string, Shape>> probes{{"sphere", Shape::sphere(0.08)},
                                                            {"box", Shape::box(V(0.06, 0.06, 0.06))},
                                                            {"capsule", Shape::capsule(0.04, 0.08)}};
    for (const auto& [name, probe] : probes) {
        Row row;
        row.probe = name;
        row.poses = poses;
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(0, 1);
        std::uniform_int_distribution<std::size_t> pick(0, bunny.triangles.size() - 1);
        std::normal_distribution<double> g;
        for (int k = 0; k < poses; ++k) {
            // Near the surface: a random point of a random triangle, moved by up to 0.25 in a random direction.
            const cdkit::Triangle& tri = bunny.triangles[pick(rng)];
            double b1 = u(rng), b2 = u(rng);
            if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
            const V on = bunny.vertices[tri[0]] + b1 * (bunny.vertices[tri[1]] - bunny.vertices[tri[0]]) +
                         b2 * (bunny.vertices[tri[2]] - bunny.vertices[tri[0]]);
            const T pose{cdbench::random_rotation(rng), on + 0.25 * u(rng) * V(g(rng), g(rng), g(rng)).normalized()};
            const T origin;
            const auto on_mesh = [&](const cdkit::ManifoldRequest& q) {
                return cdkit::collide_shapes(0, mesh, origin, 1, probe, pose, static_cast<cdkit::ManifoldCache<double>*>(nullptr), q)
                    .has_value();
            };
            const auto on_compound = [&] { return cdkit::collide_shapes(0, compound, origin, 1, probe, pose).has_value(); };
            const bool m = on_mesh(depth_off), c = on_compound();
            const bool centre_inside = inside.inside(pose.t);
            const bool solid = m || centre_inside;
            row.solid += solid;
            row.agree += c == solid;
            row.inside += !m && centre_inside && c;
            // How far from the surface a disagreeing probe is: its distance (apart) or the centre's depth (inside).
            probe.visit_convex([&](const auto& shape) {
                const auto d = cdkit::distance(rss, origin, shape, pose);
                if (c && !solid) ++row.extra, row.max_extra_gap = std::max(row.max_extra_gap, d.distance);
                if (!c && solid) {
                    ++row.missed;
                    const auto p = cdkit::penetration(rss, origin, shape, pose);
                    row.max_missed_depth = std::max(row.max_missed_depth, double(p.deepest.depth));
                }
            });
            row.mesh_ns.push_back(sample_ns([&] { return on_mesh(depth_off); }));
            row.mesh_depth_ns.push_back(sample_ns([&] { return on_mesh(depth_on); }));
            row.compound_ns.push_back(sample_ns(on_compound));
        }
        rows.push_back(std::move(row));
    }

    std::FILE* out = csv ? std::fopen(csv, "w") : nullptr;
    if (csv && !out) throw std::runtime_error(std::string("cannot write ") + csv);
    if (out) {
        cdbench::write_provenance(out, argc, argv);
        std::fprintf(out, "probe,poses,parts,voxel,solid_hits,agree,inside_only_compound,extra,max_extra_gap,missed,"
                          "max_missed_depth,mesh_us,mesh_depth_us,compound_us\n");
    }
    std::printf("%-8s %6s %6s %6s %7s %6s %9s %7s %9s %8s %10s %12s\n", "probe", "poses", "solid", "agree", "inside",
                "extra", "extra_gap", "missed", "miss_dep", "mesh_us", "mesh_dep_us", "compound_us");
    for (const Row& r : rows) {
        const double mu = cdbench::median(r.mesh_ns) / 1000, md = cdbench::median(r.mesh_depth_ns) / 1000,
                     cu = cdbench::median(r.compound_ns) / 1000;
        std::printf("%-8s %6d %6d %6d %7d %6d %9.4f %7d %9.4f %8.2f %10.2f %12.2f\n", r.probe.c_str(), r.poses, r.solid,
                    r.agree, r.inside, r.extra, r.max_extra_gap, r.missed, r.max_missed_depth, mu, md, cu);
        if (out)
            std::fprintf(out, "%s,%d,%zu,%.4f,%d,%d,%d,%d,%.4f,%d,%.4f,%.2f,%.2f,%.2f\n", r.probe.c_str(), r.poses,
                         compound.compound_shape().children().size(), voxel, r.solid, r.agree, r.inside, r.extra,
                         r.max_extra_gap, r.missed, r.max_missed_depth, mu, md, cu);
    }
    if (out) std::fclose(out);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cdkit_bench_compound: %s\n", e.what());
    return 1;
}
