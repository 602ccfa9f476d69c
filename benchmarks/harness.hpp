#pragma once
/// \file The measurement core: pose generation for protocols P1 (tumbling) and P2 (proximity, bisection to
/// contact), the timed loop over poses × modes × methods, the correctness bookkeeping, and what it all
/// produces (a Report, written out by output.cpp).

#include "bench.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace cdbench {

/// Everything the command line sets.
struct Options {
    std::vector<std::string> meshes;               ///< mesh files (already glob-expanded)
    std::vector<std::string> protocols{"p1", "p2"};
    std::vector<Mode> modes{Mode::first, Mode::all};
    std::vector<std::string> method_patterns{"*"};  ///< glob patterns over method names; "-glob" excludes
    std::string size = "quick";
    std::size_t steps = 200;       ///< P1: poses per distance (one tumbling turn)
    std::size_t rotations = 100;   ///< P2: random rotations (each with its own direction)
    double min_batch_us = 50;      ///< a pose's timed batch repeats the query until it lasts this long
    std::size_t min_reps = 8;      ///< ... and at least this often (queries shorter than min_batch_us)
    std::size_t batches = 3;       ///< timed batches per pose; the sample is the fastest (filters preemption)
    std::size_t warmup = 1;        ///< untimed queries right before the batches; the last sizes them
    double slow_query_us = 500;    ///< a query this slow is timed once after its probe, no first call
    std::uint64_t seed = 1;
    std::string split = "sah";  ///< cdkit build: median | mean | sah | pca_volume (the library default: sah)
    std::string out_dir = "build/report";
    bool quiet = false;
};

/// One mesh, normalised as BENCHMARKS.md says: scaled uniformly into [-1, 1]³ about its bounding-box centre.
struct MeshInfo {
    std::string name;   ///< file name, e.g. "bunny.obj"
    std::string path;   ///< as given
    std::size_t vertices = 0, triangles = 0;
    bool closed = false;
    std::size_t degenerate_triangles = 0, duplicate_triangles = 0, non_manifold_edges = 0;
    double scale = 1;                                      ///< normalised = (original − center) · scale
    cdkit::Vec3<double> center = cdkit::Vec3<double>::Zero();  ///< original bounding-box centre
    double radius = 0;   ///< bounding-sphere radius of the normalised mesh about the origin (max |v|)
    double load_ms = 0;
    bool identity_collides = false;  ///< sanity: the reference says two coincident copies collide
    std::size_t p2_skipped = 0;      ///< P2 rotations redrawn because the copies did not collide at s = 0
    struct Build { std::string method, family; BuildInfo info; };
    std::vector<Build> builds;
};

/// One row of results: (mesh, protocol, mode, distance class, method).
struct ResultRow {
    std::string mesh, protocol, mode, distance_kind, method, family;
    std::size_t triangles = 0;
    double distance = 0;
    std::size_t poses = 0;
    double mean_us = 0, median_us = 0, p99_us = 0, max_us = 0, min_us = 0;
    double first_call_median_us = 0;  ///< median of each pose's first, cold call (−1: slow method, not timed)
    double frac_colliding = 0;
    double bv_tests_mean = -1, tri_tests_mean = -1;  ///< −1: the method does not count them
    double contacts_mean = 0;
    std::size_t bool_disagreements = 0;   ///< poses where the boolean differs from the reference's
    std::size_t contact_mismatches = 0;   ///< all-contacts mode: poses where the pair count differs
    std::size_t probe_timed_mismatches = 0;  ///< the timed batch answered unlike the probe (must be 0)
    double ratio_vs_peer = -1;  ///< peer median / this median (> 1: faster than the peer); −1: no peer
};

/// A pose where the methods' booleans (or, in all-contacts mode, cdkit's pair counts) are not unanimous.
struct Disagreement {
    std::string mesh_path, protocol, mode, kind;
    double distance = 0;
    std::size_t pose_index = 0;
    Pose pose;
    std::vector<Outcome> answers;  ///< per method, in Report::methods order
};

struct Report {
    std::map<std::string, std::string> machine;   ///< cpu, cores, compiler, build type, date, …
    std::string provenance;                       ///< comment lines first in results.csv (provenance.hpp)
    Options options;
    std::vector<std::string> methods;             ///< measured methods, in order; methods[0] is the reference
    std::string reference, peer;                  ///< "cdkit_obb_d", "fcl_obbrss"
    std::vector<MeshInfo> meshes;
    std::vector<ResultRow> rows;
    std::vector<Disagreement> disagreements;
    double total_seconds = 0;
};

/// The P1 distances, from 1.5 down to 0: steps of 0.1 above 1.0, 0.02 below.
[[nodiscard]] std::vector<double> p1_distances();
/// The P2 offsets δ (in units of the bounding-sphere radius).
[[nodiscard]] std::vector<double> p2_deltas();

/// Loads, normalises and builds every method for each mesh, runs the selected protocols and appends to
/// `report`. Throws cdkit::Error for unreadable meshes and std::runtime_error for bad options.
void run_all(const Options& options, Report& report);

}  // namespace cdbench
