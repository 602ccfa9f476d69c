// Convex hull through reentrant Qhull (libqhull_r). Qhull is linked privately: no Qhull header leaks out.
#include <cdkit/narrowphase/convex_polyhedron.hpp>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

namespace cdkit::detail {

HullData convex_hull(const std::vector<Vec3<double>>& points) {
    const std::string src = "<convex hull>";
    if (points.size() < 4)
        throw Error(src, "point set", "needs at least 4 points, got " + std::to_string(points.size()));
    std::vector<coordT> coords;
    coords.reserve(points.size() * 3);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) throw Error(src, "point " + std::to_string(i), "not finite");
        for (int k = 0; k < 3; ++k) coords.push_back(points[i][k]);
    }
    // Qhull reports errors on errfile; keep them out of the user's stderr.
    std::FILE* err = std::tmpfile();
    qhT qh_storage;
    qhT* qh = &qh_storage;
    qh_zero(qh, err);
    char options[] = "qhull Qt";  // triangulated output
    int code = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, options, nullptr, err);
    HullData out;
    if (code == 0) {
        std::unordered_map<int, std::uint32_t> remap;
        auto index_of = [&](vertexT* v) {
            int id = qh_pointid(qh, v->point);
            auto [it, inserted] = remap.try_emplace(id, std::uint32_t(out.vertices.size()));
            if (inserted) {
                out.vertices.push_back(points[std::size_t(id)]);
                out.source_index.push_back(std::uint32_t(id));
            }
            return it->second;
        };
        facetT* facet;
        FORALLfacets {
            std::array<std::uint32_t, 3> t{};
            int k = 0;
            vertexT *vertex, **vertexp;
            FOREACHvertex_(facet->vertices) {
                if (k < 3) t[std::size_t(k)] = index_of(vertex);
                ++k;
            }
            if (k != 3) continue;  // "Qt" makes all facets simplicial; be defensive anyway
            // Orient outward with the facet's own normal.
            Vec3<double> n(facet->normal[0], facet->normal[1], facet->normal[2]);
            const auto& a = out.vertices[t[0]];
            Vec3<double> m = (out.vertices[t[1]] - a).cross(out.vertices[t[2]] - a);
            if (m.dot(n) < 0) std::swap(t[1], t[2]);
            out.triangles.push_back(t);
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(qh, &curlong, &totlong);
    if (err) std::fclose(err);
    if (code != 0 || out.triangles.size() < 4)
        throw Error(src, "point set",
                    "degenerate: the points are coplanar, collinear or coincident (no 3-D hull)");
    return out;
}

}  // namespace cdkit::detail
