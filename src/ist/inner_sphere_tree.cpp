// Inner sphere tree build: batch neural gas clustering, bounding spheres, validation.
#include "cdkit/ist/inner_sphere_tree.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <numeric>
#include <random>

namespace cdkit {
namespace {

using Vec3d = Vec3<double>;

/// Splits order[b, e) into at most k clusters by batch neural gas with volume-weighted data (magnification
/// control); reorders the range by cluster and returns the cluster boundaries (first = b, last = e).
std::vector<std::uint32_t> split_neural_gas(const std::vector<InnerSphere>& spheres, std::vector<std::uint32_t>& order,
                                            std::uint32_t b, std::uint32_t e, int k, int iterations, std::mt19937_64& rng) {
    const std::uint32_t n = e - b;
    k = std::min<int>(k, int(n));
    std::vector<Vec3d> proto;
    proto.reserve(k);
    // Seeding: one sphere drawn with probability ∝ volume, then repeatedly the sphere maximising
    // volume × squared distance to the chosen ones (a deterministic k-means++).
    {
        double total = 0;
        for (std::uint32_t i = b; i < e; ++i) total += spheres[order[i]].volume();
        double pick = std::uniform_real_distribution<double>(0, total)(rng);
        std::uint32_t first = b;
        for (std::uint32_t i = b; i < e; ++i) {
            pick -= spheres[order[i]].volume();
            if (pick <= 0) { first = i; break; }
        }
        proto.push_back(spheres[order[first]].center);
        std::vector<double> d2(n, std::numeric_limits<double>::infinity());
        while (int(proto.size()) < k) {
            double best = -1;
            std::uint32_t arg = b;
            for (std::uint32_t i = b; i < e; ++i) {
                const InnerSphere& s = spheres[order[i]];
                d2[i - b] = std::min(d2[i - b], (s.center - proto.back()).squaredNorm());
                const double score = d2[i - b] * s.volume();
                if (score > best) best = score, arg = i;
            }
            if (!(best > 0)) break;  // all centres coincide with prototypes
            proto.push_back(spheres[order[arg]].center);
        }
        k = int(proto.size());
    }
    std::vector<Vec3d> num(k);
    std::vector<double> den(k), dist(k), fall(k);
    std::vector<int> rank(k);
    const double lambda0 = std::max(0.5, k / 2.0), lambda1 = 0.01;
    for (int t = 0; t < iterations && k > 1; ++t) {
        const double lambda = lambda0 * std::pow(lambda1 / lambda0, iterations > 1 ? double(t) / (iterations - 1) : 1.0);
        for (int r = 0; r < k; ++r) fall[r] = std::exp(-r / lambda);
        std::fill(num.begin(), num.end(), Vec3d::Zero());
        std::fill(den.begin(), den.end(), 0.0);
        for (std::uint32_t i = b; i < e; ++i) {
            const InnerSphere& s = spheres[order[i]];
            for (int j = 0; j < k; ++j) dist[j] = (s.center - proto[j]).squaredNorm();
            for (int j = 0; j < k; ++j) {
                int r = 0;
                for (int l = 0; l < k; ++l) r += dist[l] < dist[j] || (dist[l] == dist[j] && l < j);
                const double w = fall[r] * s.volume();
                num[j] += w * s.center;
                den[j] += w;
            }
        }
        for (int j = 0; j < k; ++j)
            if (den[j] > 0) proto[j] = num[j] / den[j];
    }
    // Crisp assignment to the nearest prototype; stable partition by cluster.
    std::vector<int> label(n);
    std::vector<std::uint32_t> count(k + 1, 0);
    for (std::uint32_t i = b; i < e; ++i) {
        const Vec3d& c = spheres[order[i]].center;
        int arg = 0;
        double best = std::numeric_limits<double>::infinity();
        for (int j = 0; j < k; ++j) {
            const double d = (c - proto[j]).squaredNorm();
            if (d < best) best = d, arg = j;
        }
        label[i - b] = arg;
        ++count[arg + 1];
    }
    std::vector<std::uint32_t> bounds{b};
    int nonempty = 0;
    for (int j = 0; j < k; ++j) nonempty += count[j + 1] > 0;
    if (nonempty <= 1) {
        // Degenerate (coincident centres): cut the range along the longest axis into k equal parts.
        Vec3d lo = spheres[order[b]].center, hi = lo;
        for (std::uint32_t i = b; i < e; ++i) lo = lo.cwiseMin(spheres[order[i]].center), hi = hi.cwiseMax(spheres[order[i]].center);
        int axis;
        (hi - lo).maxCoeff(&axis);
        std::stable_sort(order.begin() + b, order.begin() + e,
                         [&](std::uint32_t x, std::uint32_t y) { return spheres[x].center[axis] < spheres[y].center[axis]; });
        const int parts = std::max(2, std::min<int>(k < 2 ? 2 : k, int(n)));
        for (int j = 1; j < parts; ++j) bounds.push_back(b + std::uint32_t(std::uint64_t(n) * j / parts));
        bounds.push_back(e);
        return bounds;
    }
    for (int j = 0; j < k; ++j) count[j + 1] += count[j];
    std::vector<std::uint32_t> sorted(n);
    std::vector<std::uint32_t> pos(count.begin(), count.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i) sorted[pos[label[i]]++] = order[b + i];
    std::copy(sorted.begin(), sorted.end(), order.begin() + b);
    for (int j = 1; j <= k; ++j)
        if (count[j] != count[j - 1]) bounds.push_back(b + count[j]);
    return bounds;
}

/// A sphere holding the given spheres: Bădoiu–Clarkson steps towards the farthest child from the
/// volume-weighted centroid; the radius is the exact maximum, padded by a few ulps.
void bound_children(std::vector<IstNode>& nodes, IstNode& parent) {
    const IstNode* ch = nodes.data() + parent.first;
    const std::uint32_t m = parent.count;
    Vec3d c = Vec3d::Zero();
    double wsum = 0, vol = 0;
    for (std::uint32_t j = 0; j < m; ++j) {
        const double w = std::max(ch[j].volume, 1e-300);
        c += w * ch[j].center;
        wsum += w;
        vol += ch[j].volume;
    }
    c /= wsum;
    auto reach = [&](const Vec3d& x, std::uint32_t& arg) {
        double r = -1;
        for (std::uint32_t j = 0; j < m; ++j) {
            const double d = (x - ch[j].center).norm() + ch[j].radius;
            if (d > r) r = d, arg = j;
        }
        return r;
    };
    std::uint32_t arg = 0;
    double best_r = reach(c, arg);
    Vec3d best_c = c;
    for (int t = 1; t <= 32 && m > 1; ++t) {
        const Vec3d dir = ch[arg].center - c;
        const double len = dir.norm();
        const Vec3d far = len > 0 ? Vec3d(ch[arg].center + dir * (ch[arg].radius / len)) : Vec3d(ch[arg].center + Vec3d::UnitX() * ch[arg].radius);
        c += (far - c) / double(t + 1);
        const double r = reach(c, arg);
        if (r < best_r) best_r = r, best_c = c;
    }
    parent.center = best_c;
    parent.radius = best_r * (1 + 1e-14) + 1e-300;
    parent.volume = vol;
}

}  // namespace

InnerSphereTree::InnerSphereTree(SpherePacking packing, const IstBuildOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    if (packing.spheres.empty()) throw Error("<packing>", "", "inner sphere tree: the packing holds no sphere");
    if (options.out_degree < 2 || options.out_degree > 16)
        throw Error("<packing>", "IstBuildOptions", "out_degree must lie in [2, 16]");
    if (options.iterations < 1 || options.iterations > 1000)
        throw Error("<packing>", "IstBuildOptions", "iterations must lie in [1, 1000]");
    spheres_ = std::move(packing.spheres);
    weights_ = std::move(packing.cell_weights);
    weights_.resize(spheres_.size(), 1.0);
    mesh_volume_ = packing.mesh_volume;
    out_degree_ = options.out_degree;
    const std::uint32_t n = std::uint32_t(spheres_.size());
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::mt19937_64 rng(options.seed);
    struct Work { std::uint32_t node, b, e, depth; };
    std::deque<Work> queue{{0, 0, n, 1}};
    nodes_.assign(1, IstNode{});
    std::size_t depth = 1;
    while (!queue.empty()) {
        const Work w = queue.front();
        queue.pop_front();
        depth = std::max<std::size_t>(depth, w.depth);
        if (w.e - w.b == 1) {
            IstNode& leaf = nodes_[w.node];
            leaf.first = order[w.b];
            leaf.count = 0;
            continue;
        }
        const auto bounds = split_neural_gas(spheres_, order, w.b, w.e, out_degree_, options.iterations, rng);
        const std::uint32_t first = std::uint32_t(nodes_.size());
        const std::uint32_t count = std::uint32_t(bounds.size() - 1);
        nodes_[w.node].first = first;
        nodes_[w.node].count = count;
        nodes_.resize(nodes_.size() + count);
        for (std::uint32_t j = 0; j < count; ++j) queue.push_back({first + j, bounds[j], bounds[j + 1], w.depth + 1});
    }
    // Children come after their parent: one reverse sweep fits every node after its children.
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        IstNode& node = nodes_[i];
        if (node.is_leaf()) {
            const InnerSphere& s = spheres_[node.first];
            node.center = s.center;
            node.radius = s.radius;
            node.volume = s.volume();
        } else {
            bound_children(nodes_, node);
        }
    }
    stats_.spheres = spheres_.size();
    stats_.nodes = nodes_.size();
    stats_.depth = depth;
    derive_cell_spheres();
    stats_.seconds_build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

InnerSphereTree InnerSphereTree::from_parts(std::vector<InnerSphere> spheres, std::vector<double> cell_weights,
                                            std::vector<IstNode> nodes, double mesh_volume, int out_degree,
                                            const std::string& source) {
    InnerSphereTree t;
    t.spheres_ = std::move(spheres);
    t.weights_ = std::move(cell_weights);
    t.nodes_ = std::move(nodes);
    t.mesh_volume_ = mesh_volume;
    t.out_degree_ = out_degree;
    t.validate(source);
    std::size_t depth = 0;
    std::vector<std::uint32_t> level(t.nodes_.size(), 1);
    for (std::size_t i = 0; i < t.nodes_.size(); ++i) {
        depth = std::max<std::size_t>(depth, level[i]);
        const IstNode& nd = t.nodes_[i];
        if (!nd.is_leaf())
            for (std::uint32_t j = 0; j < nd.count; ++j) level[nd.first + j] = level[i] + 1;
    }
    t.stats_.spheres = t.spheres_.size();
    t.stats_.nodes = t.nodes_.size();
    t.stats_.depth = depth;
    t.derive_cell_spheres();
    return t;
}

void InnerSphereTree::derive_cell_spheres() {
    cell_radii_.resize(spheres_.size());
    for (std::size_t i = 0; i < spheres_.size(); ++i) cell_radii_[i] = cell_sphere_radius(spheres_[i].radius, weights_[i]);
    stats_.memory_bytes = nodes_.size() * sizeof(IstNode) + spheres_.size() * (sizeof(InnerSphere) + 2 * sizeof(double));
}

void InnerSphereTree::validate(const std::string& source) const {
    auto fail = [&](const std::string& element, const std::string& why) { throw Error(source, element, why); };
    if (nodes_.empty() || spheres_.empty()) fail("tree", "no nodes or no spheres");
    if (weights_.size() != spheres_.size()) fail("tree", "cell weight count differs from the sphere count");
    if (!(mesh_volume_ > 0) || !std::isfinite(mesh_volume_)) fail("tree", "mesh volume is not a positive number");
    if (out_degree_ < 2 || out_degree_ > 16) fail("tree", "out-degree out of range [2, 16]");
    for (std::size_t i = 0; i < spheres_.size(); ++i)
        if (!spheres_[i].center.allFinite() || !(spheres_[i].radius > 0) || !std::isfinite(spheres_[i].radius) ||
            !(weights_[i] >= 1) || !std::isfinite(weights_[i]))
            fail("sphere " + std::to_string(i), "non-finite or non-positive centre, radius or weight");
    std::vector<std::uint8_t> reached(nodes_.size(), 0), used(spheres_.size(), 0);
    reached[0] = 1;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const IstNode& n = nodes_[i];
        const std::string el = "node " + std::to_string(i);
        if (!reached[i]) fail(el, "not reachable from the root");
        if (!n.center.allFinite() || !std::isfinite(n.radius) || !(n.radius >= 0) || !std::isfinite(n.volume))
            fail(el, "non-finite centre, radius or volume");
        if (n.is_leaf()) {
            if (n.first >= spheres_.size()) fail(el, "sphere index out of range");
            if (used[n.first]++) fail(el, "sphere " + std::to_string(n.first) + " is in two leaves");
            const InnerSphere& s = spheres_[n.first];
            if (n.center != s.center || n.radius != s.radius) fail(el, "leaf differs from its sphere");
            if (std::abs(n.volume - s.volume()) > 1e-9 * s.volume()) fail(el, "leaf volume differs from its sphere's");
            continue;
        }
        if (n.count > std::uint32_t(out_degree_)) fail(el, "more children than the out-degree");
        if (n.first <= i || std::size_t(n.first) + n.count > nodes_.size()) fail(el, "child range out of bounds");
        double vol = 0;
        for (std::uint32_t j = n.first; j < n.first + n.count; ++j) {
            if (reached[j]++) fail(el, "node " + std::to_string(j) + " has two parents");
            const IstNode& c = nodes_[j];
            vol += c.volume;
            if ((c.center - n.center).norm() + c.radius > n.radius * (1 + 1e-9) + 1e-12 * (n.center.norm() + n.radius))
                fail(el, "does not contain child node " + std::to_string(j));
        }
        if (std::abs(vol - n.volume) > 1e-9 * vol) fail(el, "volume differs from the sum of its children's");
    }
    for (std::size_t i = 0; i < spheres_.size(); ++i)
        if (!used[i]) fail("sphere " + std::to_string(i), "in no leaf");
}

InnerSphereTree build_inner_sphere_tree(const TriangleMesh<double>& mesh, const PackingOptions& packing,
                                        const IstBuildOptions& options) {
    return InnerSphereTree(pack_spheres(mesh, packing), options);
}

}  // namespace cdkit
