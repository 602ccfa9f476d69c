#pragma once
/// \file Sphere packing: fills a closed mesh from the inside with non-overlapping spheres of arbitrary
/// radii, the leaves of an inner sphere tree (Weller, Zachmann, "Inner sphere trees for proximity and
/// penetration queries", RSS 2009; "Inner sphere trees and their application to collision detection",
/// Virtual Realities, Springer 2011).
///
/// Method (a greedy packing at approximate inner Voronoi nodes, after the paper's voxel variant):
///  1. A grid of sample points, jittered by the seed, is classified inside/outside (InsideTest, exact
///     predicates, one ray per grid column), which also bounds each sample's distance to the surface.
///  2. Each sample's clearance is min(distance to the surface, distance to the surface of every sphere
///     placed so far); a lazy max-heap holds the samples by upper bounds of it, and a sample's surface
///     distance is measured (PointMeshDistance) only when it reaches the top, and only as far as needed
///     to tell whether it stays there.
///  3. The best sample is refined towards the inner Voronoi node of surface + spheres (the local maximum of
///     the exact clearance): a local pattern search (26 directions, steps h/2 down to h/128), then an
///     ascent along the steepest direction of the nearly active constraints (the least-norm point of the
///     hull of their gradients; Demyanov and Malozemov, "Introduction to Minimax", 1974), which follows the
///     Voronoi edges that fixed directions miss. With the look-ahead (PackingOptions::lookahead), samples
///     rank at clearance + κh until refined (by the ascent alone), and the refined ones by their refined
///     clearance, so that the largest sphere found goes first. A sphere with that clearance as radius is
///     placed, and the samples within twice its radius are updated (those it swallows die).
///  4. Repeat until the sphere count or the target coverage is reached, or no sample has room left.
/// The surface searches are seeded with a neighbouring sample's closest triangle and stop as soon as the
/// comparison they serve is decided (PointMeshDistance::PointMeshQuery); these shortcuts do not change the
/// spheres. Each radius is the exact clearance at its centre (shrunk by 1e-12 relative), so the spheres lie inside
/// the mesh and do not overlap each other, whatever the grid resolution; the resolution only limits how
/// small a gap is still found (hence the coverage reachable). Deterministic for a given seed.
///
/// Each sphere also gets a cell weight: the volume of the mesh nearest to it (its cell in the additively
/// weighted Voronoi diagram of the spheres, estimated on the samples) over its own volume. Queries use it
/// for a calibrated penetration-volume estimate (see ist_query.hpp).
///
/// Depth calibration (PackingOptions::depth_calibration, on by default): the cell weights leave the
/// outermost layer of the mesh, where the packing has most of its gaps, with too little weighted sphere
/// volume, so shallow contacts come out low. The samples' depths (distance to the surface, measured once
/// at build time; the search settles only the layer ⌊depth / layer width⌋, exactly) give the mesh's volume
/// in 16 layers two samples thick (and one deeper layer); the samples inside each sphere give its volume per layer (a sphere holding fewer than 8 samples is modelled
/// against a plane at its centre's depth). A few rounds of iterative proportional fitting then scale each
/// sphere's weight by the volume-weighted mean of its layers' ratios (mesh volume / weighted sphere
/// volume), so that the weighted sphere volume matches the mesh's layer by layer; weights stay ≥ 1.
/// The full fit overshoots (on the bunny the calibrated volume comes out high by about 0.7 of the plain
/// weights' shortfall), so the weights are the geometric blend w_cell^(1−α)·w_fit^α. The strength α is
/// derived from the object itself by default (depth_calibration_strength = derived_strength): 64 shallow
/// contacts of the object with a copy of itself, each turned by one of the 24 rotations that map the
/// sample lattice onto itself and pushed depth_calibration_contact_depth past first contact along a
/// direction spread over the sphere; their reference volume counts the lattice samples inside both (exact
/// for the lattice: samples map onto samples), their estimate is the query's (Σ lens of the cell spheres of
/// the overlapping inner-sphere pairs, radius r·∛w), and α in [0, 1] zeroes the mean relative error
/// (bisection). So α adapts to the mesh and the sphere count (bunny
/// 0.84 / 0.59 / 0.56 at 1k / 10k / 100k spheres, dragon 0.92 / 0.64 / 0.29). The correction w_fit/w_cell,
/// hence the calibration, fades as the packing gets finer and the layers' gaps close.
/// Self-contacts use the object's own shape and a contact depth, never query poses.

#include "cdkit/core/mesh.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace cdkit {

/// One inner sphere, in the mesh's model frame.
struct InnerSphere {
    Vec3<double> center = Vec3<double>::Zero();
    double radius = 0;
    [[nodiscard]] double volume() const noexcept { return 4.0 / 3.0 * 3.14159265358979323846 * radius * radius * radius; }
};

/// Radius of the cell sphere of an inner sphere of radius r and cell weight w: the ball of the cell's volume
/// w·(4/3)πr³ about the sphere's centre, r·∛w (r itself for w ≤ 1). The penetration-volume estimate sums
/// the lens volumes of cell spheres (ist_query.hpp).
[[nodiscard]] inline double cell_sphere_radius(double r, double w) noexcept { return w > 1 ? r * std::cbrt(w) : r; }

/// Parameters of pack_spheres().
struct PackingOptions {
    std::size_t max_spheres = 10000;  ///< stop after this many spheres (≥ 1)
    double target_coverage = 1.0;     ///< stop once sphere volume / mesh volume reaches this (in (0, 1])
    /// Samples along the longest bounding-box axis; 0 picks 6·∛max_spheres clamped to [48, 320].
    /// Finer grids find smaller gaps (more coverage per sphere) at a cubic cost in time and memory.
    int grid_resolution = 0;
    std::uint64_t seed = 1;  ///< jitter of the sample grid
    /// Look-ahead κ of the greedy order, in sample spacings, in [0, 4]: a sample not yet refined ranks at its
    /// clearance + κ·spacing (the gap near it may be larger than at the sample itself) and is refined before
    /// it competes with the refined ones, so each sphere placed is the largest found, not the one at the best
    /// sample. 0 places the refinement of the best sample at once (faster, less coverage).
    double lookahead = 0.5;
    /// Rescale the cell weights so that the weighted sphere volume in each layer of depth below the surface
    /// matches the mesh's (see the file comment); false keeps the plain Voronoi cell weights. Costs one
    /// distance query per sample near the surface at build time; queries are unaffected.
    bool depth_calibration = true;
    int depth_calibration_iterations = 4;  ///< fitting rounds of the depth calibration, in [0, 100]
    static constexpr double derived_strength = -1;
    /// α in [0, 1]: weights w_cell^(1−α)·w_fit^α; 0 = plain cell weights, 1 = the full fit (which overshoots);
    /// derived_strength (the default): α chosen by self-contacts of the object (see the file comment).
    double depth_calibration_strength = derived_strength;
    /// Overlap depth of the self-contacts that derive α, as a fraction of the bounding box's diagonal, in
    /// (0, 0.5] (the benchmark's shallow contacts, δ = −0.05, reach 5% of the diagonal past first contact).
    double depth_calibration_contact_depth = 0.05;
};

/// Why pack_spheres() stopped.
enum class PackingStop { max_spheres, target_coverage, no_room };

/// Work counters and timings of a packing.
struct PackingStats {
    std::size_t grid_points = 0;      ///< samples in the bounding box
    std::size_t inside_points = 0;    ///< samples classified inside (candidates)
    std::size_t distance_queries = 0; ///< point–surface distance evaluations (samples + refinement)
    double grid_spacing = 0;          ///< sample spacing
    double seconds_sampling = 0;      ///< classification + distance field
    double seconds_placing = 0;       ///< greedy placement
};

/// The output of pack_spheres(): spheres in placement order (radii almost non-increasing).
struct SpherePacking {
    std::vector<InnerSphere> spheres;
    std::vector<double> cell_weights;  ///< per sphere: its Voronoi cell volume / its volume (see the file comment)
    double mesh_volume = 0;            ///< enclosed volume of the mesh
    double sphere_volume = 0;          ///< Σ sphere volumes
    double calibration_strength = 0;   ///< the α used by the depth calibration (0 without it)
    PackingStop stop = PackingStop::no_room;
    PackingStats stats;
    /// sphere volume / mesh volume.
    [[nodiscard]] double coverage() const noexcept { return mesh_volume > 0 ? sphere_volume / mesh_volume : 0; }
    /// Coverage of the first n spheres (the packing is greedy, so this is the coverage a packing with
    /// max_spheres = n would have, up to the cell weights).
    [[nodiscard]] double coverage_of_first(std::size_t n) const noexcept {
        double v = 0;
        for (std::size_t i = 0; i < n && i < spheres.size(); ++i) v += spheres[i].volume();
        return mesh_volume > 0 ? v / mesh_volume : 0;
    }
};

/// Packs non-overlapping spheres into `mesh` (model frame). Throws cdkit::Error naming mesh.source for an
/// invalid, open, non-manifold, inconsistently oriented or zero-volume mesh (check_closed_mesh()), and for
/// options out of range. Uses TBB for the sampling stage when cdkit was built with it.
[[nodiscard]] SpherePacking pack_spheres(const TriangleMesh<double>& mesh, const PackingOptions& options = {});

}  // namespace cdkit
