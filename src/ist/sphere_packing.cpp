// Greedy inner sphere packing (see include/cdkit/ist/sphere_packing.hpp for the method).
#include "cdkit/ist/sphere_packing.hpp"

#include "cdkit/ist/closed_mesh.hpp"
#include "cdkit/ist/detail/min_norm_point.hpp"
#include "cdkit/ist/inside_test.hpp"
#include "cdkit/ist/ist_query.hpp"
#include "cdkit/ist/point_mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <unordered_map>

#if defined(CDKIT_HAS_TBB) && CDKIT_HAS_TBB
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

namespace cdkit {
namespace {

using Vec3d = Vec3<double>;

/// f(i) for i in [0, n), in parallel by chunks of at least `grain` indices.
template <class F> void parallel_for_index(std::size_t n, F&& f, std::size_t grain = 256) {
#if defined(CDKIT_HAS_TBB) && CDKIT_HAS_TBB
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
    });
#else
    (void)grain;
    for (std::size_t i = 0; i < n; ++i) f(i);
#endif
}

/// Placed spheres in a multi-level hash grid: a sphere of radius r sits in the level whose cell size is
/// the first power-of-two multiple of `base` ≥ r, in the cell holding its centre. A query for spheres
/// whose surface is nearer than T then scans, per level of size s, the cells within T + s.
class SphereIndex {
public:
    SphereIndex(const Vec3d& origin, double base) : origin_(origin), base_(base) {}

    void insert(std::uint32_t id, const InnerSphere& s) {
        int l = 0;
        double size = base_;
        while (size < s.radius && l < 40) size *= 2, ++l;
        if (std::size_t(l) >= levels_.size()) levels_.resize(l + 1);
        Level& L = levels_[l];
        L.size = size;
        L.cells[key(cell(s.center, size))].push_back(id);
    }

    /// Calls f(id) for every sphere that may have |p − c| − r < T (a superset).
    template <class F> void for_near(const Vec3d& p, double T, F&& f) const {
        for (const Level& L : levels_) {
            if (L.cells.empty()) continue;
            const double reach = T + L.size;
            const auto lo = cell(p - Vec3d::Constant(reach), L.size), hi = cell(p + Vec3d::Constant(reach), L.size);
            const double span = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
            if (span > double(L.cells.size())) {  // fewer occupied cells than cells in range: scan them all
                for (const auto& [k, ids] : L.cells)
                    for (std::uint32_t id : ids) f(id);
                continue;
            }
            for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
                for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
                    for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
                        auto it = L.cells.find(key({x, y, z}));
                        if (it == L.cells.end()) continue;
                        for (std::uint32_t id : it->second) f(id);
                    }
        }
    }

private:
    struct Level {
        double size = 0;
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
    };
    [[nodiscard]] std::array<std::int64_t, 3> cell(const Vec3d& p, double size) const noexcept {
        std::array<std::int64_t, 3> c;
        for (int k = 0; k < 3; ++k)
            c[k] = std::clamp<std::int64_t>(std::int64_t(std::floor((p[k] - origin_[k]) / size)), 0, (1 << 21) - 1);
        return c;
    }
    static std::uint64_t key(const std::array<std::int64_t, 3>& c) noexcept {
        return std::uint64_t(c[0]) | (std::uint64_t(c[1]) << 21) | (std::uint64_t(c[2]) << 42);
    }
    Vec3d origin_;
    double base_;
    std::vector<Level> levels_;
};

constexpr double pi = 3.14159265358979323846;

/// Volume of a ball of radius r below the height t (measured from its centre, along any axis).
double ball_below(double r, double t) {
    t = std::clamp(t, -r, r);
    return pi * (r + t) * (r + t) * (2 * r - t) / 3;
}

/// α where the self-contacts cannot tell: the value fitted on the bunny before α was derived (docs/ist.md).
constexpr double fallback_strength = 0.6;

/// The packing's sample lattice: origin + h·(x, y, z) for 0 ≤ x, y, z < dims; cand_of[g] ≥ 0 marks the
/// samples inside the mesh, cand_grid lists them.
struct SampleLattice {
    Vec3d origin;
    double h = 0;
    std::array<std::int64_t, 3> dims{};
    const std::vector<std::int32_t>* cand_of = nullptr;
    const std::vector<std::uint32_t>* cand_grid = nullptr;
};

/// The calibration strength α derived from the object itself, by self-contacts: 64 shallow contacts of two
/// copies of the mesh, posed as the benchmark poses its contacts (P2, δ < 0). Contact k takes a direction u
/// (nearly uniform over the sphere) and one of the 24 rotations Q that map the sample lattice onto itself;
/// the copy B = Q·(A − c) + c + s·u (c: the box centre) comes in along −u until its samples first meet A's
/// (per column along u, on a lateral grid of the sample spacing), then `depth` further; the translation is
/// rounded to lattice steps. The reference volume counts the samples inside both (a lattice sample maps to a
/// lattice sample, so no inside test is needed); the estimate is the query's own: over the overlapping pairs
/// of inner spheres, Σ lens volume of their cell spheres (radius r·∛w). α in [0, 1] zeroes the mean relative
/// error over the contacts that hold at least 32 samples, by bisection (the estimate grows with α; clamped to
/// [0, 1]); without such a contact (a very coarse lattice), fallback_strength. `blend(α)`: the weights at
/// strength α.
template <class Blend>
double self_contact_strength(const std::vector<InnerSphere>& spheres, const SampleLattice& L,
                             const Vec3d& centre, double depth, Blend&& blend) {
    // The 24 rotations of the cube: signed permutation matrices of determinant +1.
    std::vector<Eigen::Matrix3i> rotations;
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& pm : perms)
        for (int signs = 0; signs < 8; ++signs) {
            Eigen::Matrix3i q = Eigen::Matrix3i::Zero();
            for (int r = 0; r < 3; ++r) q(r, pm[r]) = (signs >> r & 1) ? -1 : 1;
            if (q.cast<double>().determinant() > 0) rotations.push_back(q);
        }
    constexpr int n_contacts = 64;
    struct Pair {
        std::uint32_t a, b;
        double d;  // centre distance
    };
    struct Contact {
        std::size_t samples = 0;
        std::vector<Pair> pairs;
    };
    std::vector<Contact> contacts(n_contacts);
    const std::vector<std::int32_t>& cand_of = *L.cand_of;
    const std::uint64_t nx = std::uint64_t(L.dims[0]), ny = std::uint64_t(L.dims[1]);
    auto lattice_index = [&](std::uint32_t g) { return Eigen::Vector3i(int(g % nx), int((g / nx) % ny), int(g / (nx * ny))); };
    auto inside = [&](const Eigen::Vector3i& y) {
        for (int i = 0; i < 3; ++i)
            if (y[i] < 0 || y[i] >= L.dims[std::size_t(i)]) return false;
        return cand_of[std::size_t((std::int64_t(y[2]) * L.dims[1] + y[1]) * L.dims[0] + y[0])] >= 0;
    };
    // The shell: samples with a lattice neighbour outside (positions relative to the centre); the first
    // contact of two copies is among them.
    std::vector<Eigen::Vector3f> shell;
    double radius = 0;
    for (std::uint32_t g : *L.cand_grid) {
        const Eigen::Vector3i x = lattice_index(g);
        bool inner = true;
        for (int i = 0; i < 3 && inner; ++i)
            for (int d : {-1, 1}) {
                Eigen::Vector3i y = x;
                y[i] += d;
                if (!inside(y)) {
                    inner = false;
                    break;
                }
            }
        if (inner) continue;
        shell.push_back((L.origin + L.h * x.cast<double>() - centre).cast<float>());
        radius = std::max(radius, double(shell.back().norm()));
    }
    parallel_for_index(contacts.size(), [&](std::size_t k) {
        const double z = 1 - (2.0 * double(k) + 1) / n_contacts, rho = std::sqrt(1 - z * z);
        const double phi = double(k) * pi * (3 - std::sqrt(5.0));  // Fibonacci lattice on the sphere
        const Vec3d u(rho * std::cos(phi), rho * std::sin(phi), z);
        const Vec3d e1 = (std::abs(u.x()) < 0.9 ? Vec3d::UnitX() : Vec3d::UnitY()).cross(u).normalized(), e2 = u.cross(e1);
        const Eigen::Matrix3i Qi = rotations[(k * 7) % rotations.size()];
        const Eigen::Matrix3d Q = Qi.cast<double>();
        // First contact along u: per lateral column of width h, A's highest and B's lowest sample.
        const int m = 2 * int(std::ceil(radius / L.h)) + 3;
        std::vector<float> a_top(std::size_t(m) * std::size_t(m), -std::numeric_limits<float>::infinity());
        std::vector<float> b_low(a_top.size(), std::numeric_limits<float>::infinity());
        auto column = [&](const Vec3d& p) {
            const int i = int(std::floor(p.dot(e1) / L.h)) + m / 2, j = int(std::floor(p.dot(e2) / L.h)) + m / 2;
            return std::size_t(std::clamp(j, 0, m - 1)) * std::size_t(m) + std::size_t(std::clamp(i, 0, m - 1));
        };
        for (const Eigen::Vector3f& ps : shell) {
            const Vec3d p = ps.cast<double>(), q = Q * p;
            float& t = a_top[column(p)];
            t = std::max(t, float(p.dot(u)));
            float& b = b_low[column(q)];
            b = std::min(b, float(q.dot(u)));
        }
        double s0 = -std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < a_top.size(); ++c)
            if (b_low[c] < std::numeric_limits<float>::infinity()) s0 = std::max(s0, double(a_top[c]) - double(b_low[c]));
        // B = Q (x − origin) + origin + h·T, with h·T ≈ c + s·u − origin − Q (c − origin).
        const Vec3d shift = (centre + (s0 - depth) * u - L.origin) / L.h - Q * ((centre - L.origin) / L.h);
        const Eigen::Vector3i T(int(std::lround(shift.x())), int(std::lround(shift.y())), int(std::lround(shift.z())));
        auto to_b = [&](const Vec3d& x) { return L.origin + Q * (x - L.origin) + L.h * T.cast<double>(); };
        Contact& c = contacts[k];
        double a_high = -std::numeric_limits<double>::infinity();
        for (float t : a_top) a_high = std::max(a_high, double(t));
        a_high += 2 * L.h;
        // Nothing of B lies below its lowest sample (a shell sample), less the rounding of T and a margin.
        double b_min = std::numeric_limits<double>::infinity();
        for (float t : b_low) b_min = std::min(b_min, double(t));
        const double b_floor = b_min + s0 - depth - 3 * L.h;
        // The reference: lattice points X inside A whose preimage Qᵀ(X − T) is inside A too, searched only in
        // the box both lattices cover and, along each row, above b_floor.
        Eigen::Vector3i lo = T, hi = T;
        for (int corner = 0; corner < 8; ++corner) {
            Eigen::Vector3i v;
            for (int i = 0; i < 3; ++i) v[i] = (corner >> i & 1) ? int(L.dims[std::size_t(i)]) - 1 : 0;
            v = Qi * v + T;
            lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        }
        for (int i = 0; i < 3; ++i) lo[i] = std::max(lo[i], 0), hi[i] = std::min(hi[i], int(L.dims[std::size_t(i)]) - 1);
        const double c0 = (L.origin - centre).dot(u);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y) {
                const double need = (b_floor - c0) / L.h - double(y) * u.y() - double(z) * u.z();  // x·u_x ≥ need
                double x0 = lo[0], x1 = hi[0];
                if (u.x() > 0) x0 = std::max(x0, std::ceil(need / u.x()));
                else if (u.x() < 0) x1 = std::min(x1, std::floor(need / u.x()));
                else if (need > 0) continue;
                for (int x = int(x0); double(x) <= x1; ++x) {
                    const Eigen::Vector3i X(x, y, z);
                    if (cand_of[std::size_t((std::int64_t(z) * L.dims[1] + y) * L.dims[0] + x)] >= 0) c.samples += inside(Qi.transpose() * (X - T));
                }
            }
        // A's spheres that reach above b_floor: the partners of B's large spheres, which the index would
        // answer by scanning whole levels of small spheres.
        std::vector<std::uint32_t> a_slab;
        for (std::size_t a = 0; a < spheres.size(); ++a)
            if ((spheres[a].center - centre).dot(u) + spheres[a].radius > b_floor) a_slab.push_back(std::uint32_t(a));
        // A local grid of cell 8h over the slab's small spheres (each in every cell its box touches); the
        // large ones are tried against every sphere of B.
        const double cell = 8 * L.h;
        auto key = [&](const Eigen::Vector3i& g) {
            return (std::uint64_t(std::uint32_t(g[0])) & 0x1fffff) | ((std::uint64_t(std::uint32_t(g[1])) & 0x1fffff) << 21) |
                   ((std::uint64_t(std::uint32_t(g[2])) & 0x1fffff) << 42);
        };
        auto cell_of = [&](const Vec3d& x) {
            return Eigen::Vector3i(int(std::floor(x.x() / cell)), int(std::floor(x.y() / cell)), int(std::floor(x.z() / cell)));
        };
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
        std::vector<std::uint32_t> a_large;
        for (std::uint32_t a : a_slab) {
            const double ra = spheres[a].radius;
            if (ra > 4 * L.h) {
                a_large.push_back(a);
                continue;
            }
            const Eigen::Vector3i g0 = cell_of(spheres[a].center - Vec3d::Constant(ra)), g1 = cell_of(spheres[a].center + Vec3d::Constant(ra));
            for (int z = g0[2]; z <= g1[2]; ++z)
                for (int y = g0[1]; y <= g1[1]; ++y)
                    for (int x = g0[0]; x <= g1[0]; ++x) grid[key({x, y, z})].push_back(a);
        }
        auto add = [&](std::uint32_t a, std::uint32_t b, const Vec3d& cb, double rb) {
            const double d = (spheres[a].center - cb).norm();
            if (d < spheres[a].radius + rb) c.pairs.push_back({a, b, d});
        };
        for (std::size_t b = 0; b < spheres.size(); ++b) {
            const Vec3d cb = to_b(spheres[b].center);
            const double rb = spheres[b].radius;
            // Skip B's spheres above A's highest sample (+ 2h: the mesh reaches less than that past its
            // samples) in every column they span.
            const Vec3d p = cb - centre;
            const double reach = rb + 2 * L.h;
            const int i0 = std::clamp(int(std::floor((p.dot(e1) - reach) / L.h)) + m / 2, 0, m - 1),
                      i1 = std::clamp(int(std::floor((p.dot(e1) + reach) / L.h)) + m / 2, 0, m - 1),
                      j0 = std::clamp(int(std::floor((p.dot(e2) - reach) / L.h)) + m / 2, 0, m - 1),
                      j1 = std::clamp(int(std::floor((p.dot(e2) + reach) / L.h)) + m / 2, 0, m - 1);
            if (p.dot(u) - rb > a_high) continue;
            if ((i1 - i0 + 1) * (j1 - j0 + 1) <= 64) {  // a large sphere is not worth the scan
                float high = -std::numeric_limits<float>::infinity();
                for (int j = j0; j <= j1; ++j)
                    for (int i = i0; i <= i1; ++i) high = std::max(high, a_top[std::size_t(j) * std::size_t(m) + std::size_t(i)]);
                if (p.dot(u) - rb > double(high) + 2 * L.h) continue;
            }
            if (rb > 4 * L.h) {
                for (std::uint32_t a : a_slab) add(a, std::uint32_t(b), cb, rb);
            } else {
                for (std::uint32_t a : a_large) add(a, std::uint32_t(b), cb, rb);
                // A pair meets in a cell both boxes touch: count it only in the first such cell.
                const Eigen::Vector3i g0 = cell_of(cb - Vec3d::Constant(rb)), g1 = cell_of(cb + Vec3d::Constant(rb));
                for (int z = g0[2]; z <= g1[2]; ++z)
                    for (int y = g0[1]; y <= g1[1]; ++y)
                        for (int x = g0[0]; x <= g1[0]; ++x) {
                            const auto it = grid.find(key({x, y, z}));
                            if (it == grid.end()) continue;
                            for (std::uint32_t a : it->second) {
                                const double ra = spheres[a].radius;
                                const Eigen::Vector3i lo_a = cell_of(spheres[a].center - Vec3d::Constant(ra)).cwiseMax(g0);
                                if (lo_a != Eigen::Vector3i(x, y, z)) continue;
                                add(a, std::uint32_t(b), cb, rb);
                            }
                        }
            }
        }
    }, 1);
    const double per_sample = L.h * L.h * L.h;
    auto mean_error = [&](double alpha) {
        const std::vector<double> w = blend(alpha);
        std::vector<double> cell(spheres.size());
        for (std::size_t i = 0; i < spheres.size(); ++i) cell[i] = cell_sphere_radius(spheres[i].radius, w[i]);
        double sum = 0;
        int used = 0;
        for (const Contact& c : contacts) {
            if (c.samples < 32) continue;
            double est = 0;
            for (const Pair& q : c.pairs) est += sphere_intersection_volume(cell[q.a], cell[q.b], q.d);
            sum += est / (double(c.samples) * per_sample) - 1, ++used;
        }
        return used ? sum / used : std::numeric_limits<double>::quiet_NaN();
    };
    if (std::isnan(mean_error(0))) return fallback_strength;  // no contact holds enough samples (a very coarse lattice)
    double a = 0, b = 1;
    if (mean_error(a) >= 0) return 0;
    if (mean_error(b) <= 0) return 1;
    for (int it = 0; it < 20; ++it) {
        const double mid = (a + b) / 2;
        (mean_error(mid) < 0 ? a : b) = mid;
    }
    return (a + b) / 2;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

SpherePacking pack_spheres(const TriangleMesh<double>& mesh, const PackingOptions& options) {
    if (options.max_spheres < 1) throw Error(mesh.source, "PackingOptions", "max_spheres must be at least 1");
    if (!(options.target_coverage > 0 && options.target_coverage <= 1))
        throw Error(mesh.source, "PackingOptions", "target_coverage must lie in (0, 1]");
    if (options.grid_resolution != 0 && (options.grid_resolution < 4 || options.grid_resolution > 1024))
        throw Error(mesh.source, "PackingOptions", "grid_resolution must be 0 (auto) or in [4, 1024]");
    if (options.depth_calibration_iterations < 0 || options.depth_calibration_iterations > 100)
        throw Error(mesh.source, "PackingOptions", "depth_calibration_iterations must lie in [0, 100]");
    if (!(options.depth_calibration_strength == PackingOptions::derived_strength ||
          (options.depth_calibration_strength >= 0 && options.depth_calibration_strength <= 1)))
        throw Error(mesh.source, "PackingOptions", "depth_calibration_strength must lie in [0, 1] or be derived_strength (-1)");
    if (!(options.depth_calibration_contact_depth > 0 && options.depth_calibration_contact_depth <= 0.5))
        throw Error(mesh.source, "PackingOptions", "depth_calibration_contact_depth must lie in (0, 0.5]");
    if (!(options.lookahead >= 0 && options.lookahead <= 4))
        throw Error(mesh.source, "PackingOptions", "lookahead must lie in [0, 4]");

    SpherePacking out;
    out.mesh_volume = check_closed_mesh(mesh);
    const auto t0 = std::chrono::steady_clock::now();

    Vec3d lo = Vec3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Triangle& t : mesh.triangles)
        for (Index v : t) lo = lo.cwiseMin(mesh.vertices[v]), hi = hi.cwiseMax(mesh.vertices[v]);
    const double extent = (hi - lo).maxCoeff();
    const int res = options.grid_resolution > 0
                        ? options.grid_resolution
                        : std::clamp(int(std::lround(6 * std::cbrt(double(options.max_spheres)))), 48, 320);
    const double h = extent / res;
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Vec3d jitter(unit(rng), unit(rng), unit(rng));
    const Vec3d origin = lo + jitter * h;
    std::array<std::int64_t, 3> dims;
    for (int k = 0; k < 3; ++k) dims[k] = std::max<std::int64_t>(1, std::int64_t(std::floor((hi[k] - origin[k]) / h)) + 1);
    const std::size_t total = std::size_t(dims[0] * dims[1] * dims[2]);
    if (total > (std::size_t(1) << 31)) throw Error(mesh.source, "PackingOptions", "grid_resolution too large for this mesh");
    auto grid_point = [&](std::size_t g) {
        const std::int64_t x = std::int64_t(g % dims[0]), y = std::int64_t((g / dims[0]) % dims[1]),
                           z = std::int64_t(g / (dims[0] * dims[1]));
        return Vec3d(origin.x() + x * h, origin.y() + y * h, origin.z() + z * h);
    };

    // 1. Samples. One ray per grid column gives every sample's inside flag and an upper bound of its surface
    //    distance (the nearest crossing along the column). Samples within 1e-9·extent of a crossing, and
    //    columns that graze an edge, take the exact per-point test instead of the rounded crossing positions.
    const InsideTest inside(mesh);
    const PointMeshDistance surface(mesh);
    std::vector<std::uint8_t> is_in(total, 0);
    std::vector<double> bound(total, 0.0);
    const std::size_t columns = std::size_t(dims[1] * dims[2]);
    const double eps = 1e-9 * extent;
    parallel_for_index(columns, [&](std::size_t col) {
        const std::int64_t y = std::int64_t(col % dims[1]), z = std::int64_t(col / dims[1]);
        const std::size_t base = std::size_t(z * dims[1] + y) * dims[0];
        const double py = origin.y() + y * h, pz = origin.z() + z * h;
        std::vector<std::pair<double, int>> cross;
        if (!inside.line_crossings(py, pz, cross)) {
            for (std::int64_t x = 0; x < dims[0]; ++x) {
                const Vec3d p(origin.x() + x * h, py, pz);
                is_in[base + x] = inside.inside(p) ? 1 : 0;
                bound[base + x] = std::numeric_limits<double>::infinity();
            }
            return;
        }
        std::sort(cross.begin(), cross.end());
        int ahead = 0;
        for (const auto& c : cross) ahead += c.second;
        std::size_t next = 0;  // first crossing with t > x
        for (std::int64_t x = 0; x < dims[0]; ++x) {
            const double px = origin.x() + x * h;
            while (next < cross.size() && cross[next].first <= px) ahead -= cross[next++].second;
            const double gap_prev = next > 0 ? px - cross[next - 1].first : std::numeric_limits<double>::infinity();
            const double gap_next = next < cross.size() ? cross[next].first - px : std::numeric_limits<double>::infinity();
            const double gap = std::min(gap_prev, gap_next);
            is_in[base + x] = gap > eps ? (ahead != 0) : inside.inside(Vec3d(px, py, pz));
            bound[base + x] = gap;
        }
    });
    std::vector<std::int32_t> cand_of(total, -1);
    std::vector<std::uint32_t> cand_grid;
    for (std::size_t g = 0; g < total; ++g)
        if (is_in[g]) cand_of[g] = std::int32_t(cand_grid.size()), cand_grid.push_back(std::uint32_t(g));
    is_in = {};
    const std::size_t n_cand = cand_grid.size();
    // key: an upper bound of the clearance; exact[c] once the surface distance has been measured (lazily,
    // when the sample reaches the top of the heap: most samples are swallowed by spheres before that).
    std::vector<double> key(n_cand);
    std::vector<std::uint8_t> exact(n_cand, 0);
    // The closest triangle found for a sample, if measured (seeds the distance queries of its neighbours
    // and of its refinement), and its exact surface distance once known (+inf until then).
    std::vector<Index> near_tri(n_cand, PointMeshDistance::no_hint);
    std::vector<double> surface_dist(n_cand, std::numeric_limits<double>::infinity());
    for (std::size_t c = 0; c < n_cand; ++c) key[c] = bound[cand_grid[c]];
    bound = {};
    out.stats.grid_points = total;
    out.stats.inside_points = n_cand;
    out.stats.grid_spacing = h;
    out.stats.seconds_sampling = seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();

    // 2–4. Greedy placement from a lazy max-heap: each live sample has one entry, whose value is an upper
    // bound of key[c] (keys only decrease). Lowering a key does not touch the heap; an entry that reaches
    // the top with an outdated value goes back with the current one. The top entry, once current, is the
    // largest key, as every other entry bounds its own from above; few samples ever reach the top, so this
    // costs far fewer heap operations than pushing every decrease.
    std::vector<std::int32_t> owner(n_cand, -1);
    std::vector<std::uint8_t> alive(n_cand, 1);
    using Entry = std::pair<double, std::uint32_t>;
    std::vector<Entry> heap;
    heap.reserve(n_cand);
    for (std::size_t c = 0; c < n_cand; ++c)
        if (key[c] > 0) heap.emplace_back(key[c], std::uint32_t(c));
        else alive[c] = 0;
    std::make_heap(heap.begin(), heap.end());
    // Cells of 4h at the finest level: the neighbourhoods asked for reach a few h, and smaller cells cost
    // more hash lookups than the extra spheres they filter out (bunny, 10k: a third less placement time).
    SphereIndex index(lo - Vec3d::Constant(h), 4 * h);
    const double min_radius = 1e-9 * extent;
    const double target_volume = options.target_coverage * out.mesh_volume;
    std::vector<std::uint32_t> near;
    struct AscentSite {
        Vec3d center;
        double radius;
    };
    std::vector<AscentSite> ascent_sites;
    std::vector<Vec3d> ascent_grads;
    std::vector<double> ascent_vals;
    std::vector<std::uint32_t> ascent_bind;
    // Pattern directions: the 26 neighbours of a cube (axes, face and space diagonals). With the axes alone
    // the search stalls on ridges of the clearance (two constraints equally near) that run diagonally; the
    // diagonals follow them (dragon, 10k spheres: coverage 79.0% → 81.1%; bunny 86.2% → 87.6%).
    static const std::vector<Vec3d> dirs = [] {
        std::vector<Vec3d> d;
        for (int n = 1; n <= 3; ++n)
            for (int k = -1; k <= 1; ++k)
                for (int j = -1; j <= 1; ++j)
                    for (int i = -1; i <= 1; ++i)
                        if (std::abs(i) + std::abs(j) + std::abs(k) == n) d.push_back(Vec3d(i, j, k).normalized());
        return d;
    }();
    // Look-ahead (options.lookahead = κ): a sample's rank is not its clearance but an estimate of the largest
    // clearance near it, so that the sphere placed is the largest one available, not the one at the best
    // sample (on a grid of spacing h, the best sample can sit in a smaller gap than a sample just below
    // it). A sample not yet refined ranks at clearance + κh; at the top it is refined (Voronoi ascent) and
    // goes back ranked by the refined clearance; a refined sample that comes back to the top is polished
    // (pattern search, ascent) and placed. A sphere placed near a refined centre that lowers its clearance
    // turns it back into an unrefined sample, ranked no higher than its refined clearance was (ranks only
    // decrease, as the lazy heap needs).
    struct Refined {
        Vec3d x;          // refined centre
        double g;         // its exact clearance (as long as `valid`)
        double f;         // the sample's clearance when refined: fixes the neighbourhood searched
        bool valid;
    };
    const double look = options.lookahead * h;
    std::vector<Refined> refined;
    std::vector<std::int32_t> refined_of(look > 0 ? n_cand : 0, -1);
    auto rank = [&](std::uint32_t c) {
        if (look <= 0) return key[c];
        const std::int32_t s = refined_of[c];
        if (s < 0) return key[c] + look;
        const Refined& R = refined[std::size_t(s)];
        return R.valid ? R.g : std::min(key[c] + look, R.g);
    };
    if (look > 0) {
        for (Entry& e : heap) e.first = rank(e.second);
        std::make_heap(heap.begin(), heap.end());
    }
    out.stop = PackingStop::no_room;
    while (true) {
        if (out.spheres.size() >= options.max_spheres) { out.stop = PackingStop::max_spheres; break; }
        if (out.sphere_volume >= target_volume) { out.stop = PackingStop::target_coverage; break; }
        if (heap.empty()) break;
        std::pop_heap(heap.begin(), heap.end());
        // Plain variables, not a structured binding: lambdas below capture them (clang 14 cannot capture bindings).
        const double top = heap.back().first;
        const auto c0 = heap.back().second;
        heap.pop_back();
        if (!alive[c0]) continue;
        if (top != rank(c0)) {  // outdated
            heap.emplace_back(rank(c0), c0);
            std::push_heap(heap.begin(), heap.end());
            continue;
        }
        if (!exact[c0]) {
            // Measure the surface distance now and requeue. Only a clearance above the next rank (less the
            // look-ahead) keeps c0 on top, so the search may stop at the first triangle at most that far: c0
            // then goes back with that lower upper bound (most samples measured here sink and are swallowed
            // before they come back). Seeded with the closest triangle already known for c0 or a grid neighbour.
            const Vec3d p = grid_point(cand_grid[c0]);
            PointMeshDistance::PointMeshQuery o;
            o.max_distance = key[c0];
            o.stop_at = heap.empty() ? -1.0 : heap.front().first - look;
            double hint_d2 = std::numeric_limits<double>::infinity();
            auto try_hint = [&](std::int64_t gi) {
                const std::int32_t c = cand_of[std::size_t(gi)];
                if (c < 0 || near_tri[std::size_t(c)] == PointMeshDistance::no_hint) return;
                const Triangle& t = mesh.triangles[near_tri[std::size_t(c)]];
                const double d2 = (closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]) - p).squaredNorm();
                if (d2 < hint_d2) hint_d2 = d2, o.hint = near_tri[std::size_t(c)];
            };
            const std::int64_t g0 = cand_grid[c0];
            const std::int64_t stride[3] = {1, dims[0], dims[0] * dims[1]};
            const std::int64_t at[3] = {g0 % dims[0], (g0 / dims[0]) % dims[1], g0 / (dims[0] * dims[1])};
            try_hint(g0);
            for (int k = 0; k < 3; ++k) {
                if (at[k] > 0) try_hint(g0 - stride[k]);
                if (at[k] + 1 < dims[k]) try_hint(g0 + stride[k]);
            }
            ++out.stats.distance_queries;
            const PointMeshClosest q = surface.query(p, o);
            exact[c0] = !(q.distance <= o.stop_at);  // a search that ran to the end (ties rerun once, harmlessly)
            if (q.distance < key[c0]) {
                key[c0] = q.distance, near_tri[c0] = q.triangle;
                if (exact[c0]) surface_dist[c0] = q.distance;
            }
            heap.emplace_back(rank(c0), c0);
            std::push_heap(heap.begin(), heap.end());
            continue;
        }
        if (top <= min_radius) break;
        const std::int32_t slot = look > 0 ? refined_of[c0] : -1;
        const bool polish = slot >= 0 && refined[std::size_t(slot)].valid;  // refined before: polish and place
        const double f0 = polish ? refined[std::size_t(slot)].f : key[c0];
        const Vec3d p0 = grid_point(cand_grid[c0]);
        // The refined centre stays within M of p0; spheres farther than T from p0 cannot bound the clearance
        // anywhere in that ball below f0 + M, which caps the radius.
        const double M = std::min(2 * h, f0 + 0.5 * h);
        const double T = f0 + 2 * M;
        near.clear();
        index.for_near(p0, T, [&](std::uint32_t id) {
            const InnerSphere& s = out.spheres[id];
            if ((p0 - s.center).norm() - s.radius < T) near.push_back(id);
        });
        // The clearance at y where it exceeds `beat`; at most `beat` otherwise (then y loses the comparison
        // anyway, so the surface search may stop at the first triangle that close). `tri`: in, a nearby
        // triangle to seed the search; out, y's closest triangle when the surface bounds the clearance.
        auto clearance = [&](const Vec3d& y, double beat, Index& tri) {
            double g = f0 + M;
            for (std::uint32_t id : near) g = std::min(g, (y - out.spheres[id].center).norm() - out.spheres[id].radius);
            if (g <= std::max(beat, 0.0)) return g;
            ++out.stats.distance_queries;
            PointMeshDistance::PointMeshQuery o;
            o.max_distance = g, o.hint = tri, o.stop_at = beat;
            const PointMeshClosest q = surface.query(y, o);
            if (q.distance < g) tri = q.triangle;
            return std::min(g, q.distance);
        };
        Vec3d x = p0;
        Index tri_x = near_tri[c0];
        double g;
        if (polish) {
            x = refined[std::size_t(slot)].x, g = refined[std::size_t(slot)].g;
        } else if (surface_dist[c0] < std::numeric_limits<double>::infinity()) {  // clearance(p0) without a new search
            g = std::min(f0 + M, surface_dist[c0]);
            for (std::uint32_t id : near) g = std::min(g, (p0 - out.spheres[id].center).norm() - out.spheres[id].radius);
        } else {
            g = clearance(p0, -1.0, tri_x);
        }
        // Pattern search towards the inner Voronoi node, for the sphere to be placed (the look-ahead's
        // refinements use the cheaper ascent alone). A step shorter than the clearance stays inside the
        // empty ball around x, so the centre never crosses the surface.
        for (double step = 0.5 * h; (look <= 0 || polish) && step > h / 128;) {
            const double s = std::min(step, 0.5 * g);
            if (s <= h / 128) break;
            double best = g;
            Vec3d bx = x;
            Index btri = tri_x;
            for (const Vec3d& d : dirs) {
                const Vec3d y = x + s * d;
                if ((y - p0).norm() > M) continue;
                Index ty = tri_x;
                const double gy = clearance(y, best, ty);
                if (gy > best) best = gy, bx = y, btri = ty;
            }
            if (best > g) x = bx, g = best, tri_x = btri;
            else step *= 0.5;
        }
        // Ascent to the inner Voronoi node. The pattern search stalls where three or four constraints are
        // equally near (a Voronoi edge: the clearance grows only along one line, which no fixed direction
        // follows). Model the clearance as the least of |y − c| − r over the nearby spheres and the surface
        // points found so far (an upper bound: each surface point bounds the surface distance from above);
        // step along the steepest ascent of the nearly active constraints — the point of least norm in the
        // hull of their gradients, zero at a Voronoi node — to where the model peaks; measure the surface
        // there, and keep the step if the clearance grew, else keep only the surface point (a sharper model).
        {
            const double cap = f0 + M;
            ascent_sites.clear();
            for (std::uint32_t id : near) ascent_sites.push_back({out.spheres[id].center, out.spheres[id].radius});
            auto add_surface = [&](const Vec3d& y, double reach) {
                PointMeshDistance::PointMeshQuery o;
                o.max_distance = reach, o.hint = tri_x;
                ++out.stats.distance_queries;
                const PointMeshClosest q = surface.query(y, o);
                if (q.distance < reach) ascent_sites.push_back({q.point, 0.0});
                return q;
            };
            auto model = [&](const Vec3d& y) {  // over the sites that can bind within the step (ascent_bind)
                double m = cap;
                for (std::uint32_t i : ascent_bind) m = std::min(m, (y - ascent_sites[i].center).norm() - ascent_sites[i].radius);
                return m;
            };
            {
                const PointMeshClosest q = add_surface(x, g * 1.25 + h / 64);
                if (q.distance < std::numeric_limits<double>::infinity()) tri_x = q.triangle;
            }
            // "Nearly active" within tol·g: a step should not run straight into those; at a node of that
            // coarse model the tolerance shrinks, which resolves nodes closer than 5% of the clearance.
            double tol = 0.05;
            for (int it = 0; it < 32; ++it) {
                ascent_grads.clear();
                ascent_vals.clear();
                for (const AscentSite& a : ascent_sites) {
                    const Vec3d d = x - a.center;
                    const double dn = d.norm();
                    ascent_vals.push_back(dn - a.radius);
                    if (dn - a.radius <= g * (1 + tol) + h / 4096 && dn > 0) ascent_grads.push_back(d / dn);
                }
                if (ascent_grads.empty() || ascent_grads.size() > 12) break;
                const Vec3d z = detail::min_norm_in_hull(ascent_grads);
                if (z.norm() < 1e-3) {  // a Voronoi node: no direction raises every near constraint
                    if (tol < 0.002) break;
                    tol *= 0.25;
                    continue;
                }
                const Vec3d u = z.normalized();
                // Longest step: inside the empty ball around x (so inside the mesh) and the ball of radius M around p0.
                const Vec3d w = x - p0;
                const double bq = w.dot(u), cq = w.squaredNorm() - M * M;
                const double smax = std::min(0.9 * g, -bq + std::sqrt(std::max(0.0, bq * bq - cq)));
                if (!(smax > h / 1024)) break;
                // A step of s moves each constraint by at most s, and the model at the end stays below
                // g·(1 + tol) + s: sites farther than that plus s cannot bind anywhere along the step.
                ascent_bind.clear();
                for (std::uint32_t i = 0; i < ascent_vals.size(); ++i)
                    if (ascent_vals[i] <= g * (1 + tol) + h / 4096 + 2 * smax) ascent_bind.push_back(i);
                double best_s = 0, best_m = g;
                for (int k = 1; k <= 16; ++k) {
                    const double sk = smax * k / 16;
                    const double mk = model(x + sk * u);
                    if (mk > best_m) best_m = mk, best_s = sk;
                }
                if (best_s == 0 || best_m <= g * (1 + 1e-9)) break;
                const Vec3d y = x + best_s * u;
                double gy = cap;
                for (std::uint32_t id : near) gy = std::min(gy, (y - out.spheres[id].center).norm() - out.spheres[id].radius);
                const PointMeshClosest q = add_surface(y, gy);
                gy = std::min(gy, q.distance);
                if (gy > g) {
                    x = y, g = gy;
                    if (q.distance < std::numeric_limits<double>::infinity()) tri_x = q.triangle;
                }
            }
        }
        if (look > 0 && !polish) {  // look-ahead: rank c0 by its refined clearance, place later
            const Refined R{x, g, f0, true};
            if (slot >= 0) refined[std::size_t(slot)] = R;
            else refined_of[c0] = std::int32_t(refined.size()), refined.push_back(R);
            heap.emplace_back(rank(c0), c0);
            std::push_heap(heap.begin(), heap.end());
            continue;
        }
        const double r = g * (1 - 1e-12);
        if (!(r > min_radius)) continue;
        const std::uint32_t sid = std::uint32_t(out.spheres.size());
        out.spheres.push_back({x, r});
        out.sphere_volume += out.spheres.back().volume();
        index.insert(sid, out.spheres.back());
        // Samples within r + g ≤ 2g can have their clearance lowered (every live key and every valid refined
        // clearance is ≤ g); refined centres lie within M ≤ 2h of their samples.
        const double reach = 2 * g + (look > 0 ? 2 * h : 0.0);
        std::array<std::int64_t, 3> a, b;
        for (int k = 0; k < 3; ++k) {
            a[k] = std::max<std::int64_t>(0, std::int64_t(std::ceil((x[k] - reach - origin[k]) / h)));
            b[k] = std::min<std::int64_t>(dims[k] - 1, std::int64_t(std::floor((x[k] + reach - origin[k]) / h)));
        }
        for (std::int64_t z = a[2]; z <= b[2]; ++z)
            for (std::int64_t y = a[1]; y <= b[1]; ++y)
                for (std::int64_t xi = a[0]; xi <= b[0]; ++xi) {
                    const std::size_t gi = std::size_t((z * dims[1] + y) * dims[0] + xi);
                    const std::int32_t c = cand_of[gi];
                    if (c < 0) continue;
                    if (look > 0 && refined_of[std::size_t(c)] >= 0) {
                        Refined& R = refined[std::size_t(refined_of[std::size_t(c)])];
                        if (R.valid && (R.x - x).norm() - r < R.g) R.valid = false;
                    }
                    const double d = (grid_point(gi) - x).norm() - r;
                    if (d >= key[c]) continue;
                    key[c] = d;
                    owner[c] = std::int32_t(sid);
                    if (!alive[c]) continue;
                    if (d <= 0) alive[c] = 0;
                }
        if (alive[c0]) heap.emplace_back(rank(c0), c0), std::push_heap(heap.begin(), heap.end());  // c0 has no entry now
    }

    // Cell weights: each inside sample belongs to the sphere whose surface is nearest.
    std::vector<double> cell_count(out.spheres.size(), 0.0);
    if (!out.spheres.empty()) {
        for (std::size_t c = 0; c < n_cand; ++c) {
            std::int32_t o = owner[c];
            if (o < 0) {  // never reached by a sphere's update: search outwards
                const Vec3d p = grid_point(cand_grid[c]);
                double best = std::numeric_limits<double>::infinity();
                for (double T = 2 * h;; T *= 2) {
                    index.for_near(p, T, [&](std::uint32_t id) {
                        const double d = (p - out.spheres[id].center).norm() - out.spheres[id].radius;
                        if (d < best) best = d, o = std::int32_t(id);
                    });
                    if ((o >= 0 && best < T) || T > 4 * extent) break;
                }
            }
            if (o >= 0) cell_count[std::size_t(o)] += 1;
        }
    }
    out.cell_weights.resize(out.spheres.size());
    const double per_sample = n_cand ? out.mesh_volume / double(n_cand) : 0.0;
    for (std::size_t i = 0; i < out.spheres.size(); ++i)
        out.cell_weights[i] = std::max(1.0, cell_count[i] * per_sample / out.spheres[i].volume());

    // Depth profile: make the weighted sphere volume match the mesh's volume in each layer of depth (distance
    // to the surface), so that a shallow contact, which only reaches the outer layers, sees the right density.
    if (options.depth_calibration && options.depth_calibration_strength != 0 && options.depth_calibration_iterations > 0 &&
        !out.spheres.empty()) {
        // 16 layers two samples thick, then one for everything deeper; one sample per layer was noisier
        // (docs/ist.md).
        constexpr int layers = 16;
        const double lw = 2 * h;
        const double D = layers * lw;
        std::vector<std::uint8_t> layer_of(n_cand, std::uint8_t(layers));
        // By runs of consecutive samples along x (the candidates are in grid order), each query seeded with
        // the triangle found for the previous sample, a few h away; the quantum stops each search once the
        // layer is certain (layers are exact, so the weights do not depend on the seeding or the runs).
        constexpr std::size_t run = 64;
        parallel_for_index((n_cand + run - 1) / run, [&](std::size_t b) {
            Index tri = PointMeshDistance::no_hint;
            for (std::size_t c = b * run; c < std::min(n_cand, (b + 1) * run); ++c) {
                if (key[c] < 0 && -key[c] >= D) continue;  // deep inside its sphere (spheres lie inside the mesh)
                PointMeshDistance::PointMeshQuery o;
                o.max_distance = D, o.hint = tri, o.quantum = lw;  // only the layer ⌊d / lw⌋ is used
                const PointMeshClosest q = surface.query(grid_point(cand_grid[c]), o);
                if (q.distance < D) layer_of[c] = std::uint8_t(std::min(layers - 1, int(q.distance / lw))), tri = q.triangle;
            }
        });
        const std::size_t n = out.spheres.size();
        std::vector<double> mesh_layer(layers + 1, 0.0);
        std::vector<std::array<double, layers + 1>> share(n);  // sphere volume per layer
        std::vector<double> inside_count(n, 0.0);
        for (std::size_t i = 0; i < n; ++i) share[i].fill(0.0);
        for (std::size_t c = 0; c < n_cand; ++c) {
            mesh_layer[layer_of[c]] += per_sample;
            if (key[c] < 0 && owner[c] >= 0) share[std::size_t(owner[c])][layer_of[c]] += 1, inside_count[std::size_t(owner[c])] += 1;
        }
        layer_of = {};
        // Spheres holding few samples: model the surface near them as a plane at the distance of their centre.
        const auto below = ball_below;
        parallel_for_index(n, [&](std::size_t i) {
            const InnerSphere& s = out.spheres[i];
            if (inside_count[i] >= 8) {
                for (double& x : share[i]) x *= s.volume() / inside_count[i];
                return;
            }
            const double d = std::max(s.radius, std::min(surface.query(s.center, D + s.radius).distance, D + s.radius));
            for (int k = 0; k <= layers; ++k) {
                const double top = k == layers ? std::numeric_limits<double>::infinity() : (k + 1) * lw;
                share[i][k] = below(s.radius, top - d) - below(s.radius, k * lw - d);
            }
        });
        std::vector<double> w = out.cell_weights;
        for (int iter = 0; iter < options.depth_calibration_iterations; ++iter) {
            std::array<double, layers + 1> f{};
            for (std::size_t i = 0; i < n; ++i)
                for (int k = 0; k <= layers; ++k) f[k] += w[i] * share[i][k];
            for (int k = 0; k <= layers; ++k) f[k] = f[k] > 0 ? mesh_layer[k] / f[k] : 1.0;
            for (std::size_t i = 0; i < n; ++i) {
                double v = 0, fv = 0;
                for (int k = 0; k <= layers; ++k) v += share[i][k], fv += f[k] * share[i][k];
                if (v > 0) w[i] *= fv / v;
            }
        }
        // Partial strength: the full fit overshoots (docs/ist.md), w = w_cell^(1−α)·w_fit^α.
        std::vector<double> log0(n), log1(n);
        for (std::size_t i = 0; i < n; ++i) log0[i] = std::log(out.cell_weights[i]), log1[i] = std::log(std::max(1.0, w[i]));
        auto blend = [&](double a) {
            std::vector<double> b(n);
            for (std::size_t i = 0; i < n; ++i) b[i] = std::max(1.0, std::exp((1 - a) * log0[i] + a * log1[i]));
            return b;
        };
        double alpha = options.depth_calibration_strength;
        if (alpha < 0) {
            const SampleLattice lattice{origin, h, dims, &cand_of, &cand_grid};
            alpha = self_contact_strength(out.spheres, lattice, (lo + hi) / 2, (hi - lo).norm() * options.depth_calibration_contact_depth, blend);
        }
        out.calibration_strength = alpha;
        out.cell_weights = blend(alpha);
    }
    out.stats.seconds_placing = seconds_since(t1);
    return out;
}

}  // namespace cdkit
