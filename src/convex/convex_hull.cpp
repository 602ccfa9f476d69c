// Convex hull through reentrant Qhull (libqhull_r). Qhull is linked privately: no Qhull header leaks out.
#include <cdkit/narrowphase/convex_polyhedron.hpp>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
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
    // Default options: coplanar facets are merged (Qhull's 'C-0' pre-merge in 3-d), so a box has six
    // quadrilateral faces. The faces are kept as polygons (closest-feature tracking needs real faces and
    // edges) and fan-triangulated for triangles().
    char options[] = "qhull";
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
            // The facet's vertices in cyclic order around it (qh_facet3vertex walks the ridges).
            setT* loop_set = qh_facet3vertex(qh, facet);
            std::vector<std::uint32_t> loop;
            vertexT *vertex, **vertexp;
            FOREACHvertex_(loop_set) loop.push_back(index_of(vertex));
            qh_settempfree(qh, &loop_set);
            if (loop.size() < 3) continue;
            // Orient the loop counter-clockwise seen from outside, with the facet's own normal.
            Vec3<double> n(facet->normal[0], facet->normal[1], facet->normal[2]);
            Vec3<double> newell = Vec3<double>::Zero();
            for (std::size_t k = 0; k < loop.size(); ++k)
                newell += out.vertices[loop[k]].cross(out.vertices[loop[(k + 1) % loop.size()]]);
            if (newell.dot(n) < 0) std::reverse(loop.begin(), loop.end());
            for (std::size_t k = 1; k + 1 < loop.size(); ++k) out.triangles.push_back({loop[0], loop[k], loop[k + 1]});
            out.faces.push_back(std::move(loop));
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(qh, &curlong, &totlong);
    if (err) std::fclose(err);
    if (code != 0 || out.triangles.size() < 4 || out.faces.size() < 4)
        throw Error(src, "point set",
                    "degenerate: the points are coplanar, collinear or coincident (no 3-D hull)");
    return out;
}

}  // namespace cdkit::detail
