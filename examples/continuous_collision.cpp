// Tunnelling and continuous collision detection. A small sheet of cloth (a grid of triangles) falls fast onto a
// thin plate: at the start of the step it is above the plate, at the end below it, and a discrete test at either
// instant sees no contact — the sheet passed through. Continuous collision (self_ccd over the sheet and the plate
// as one mesh) finds the first time of contact during the step, and which vertex–face or edge–edge pair it is.
// Then one vertex–face query on its own, as a simulator's narrow phase would call it.
// Usage: continuous_collision   (exits non-zero when the contact is not found)
#include <cdkit/ccd/deformable_ccd.hpp>
#include <cdkit/ccd/vertex_face.hpp>

#include <cstdio>
#include <vector>

using V = cdkit::Vec3<double>;

int main() try {
    // The plate: two triangles in z = 0 over [-1, 1]². The sheet: an n × n grid over [-0.5, 0.5]², tilted a little,
    // falling from z ≈ 0.5 to z ≈ −0.5 in one step (a step far too long for its speed).
    std::vector<V> start{V(-1, -1, 0), V(1, -1, 0), V(1, 1, 0), V(-1, 1, 0)};
    std::vector<cdkit::Triangle> triangles{{0, 1, 2}, {0, 2, 3}};
    const int n = 8;
    const cdkit::Index first = cdkit::Index(start.size());
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const double x = -0.5 + double(i) / n, y = -0.5 + double(j) / n;
            start.emplace_back(x, y, 0.5 + 0.1 * x);
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const cdkit::Index a = first + cdkit::Index(i * (n + 1) + j), b = a + 1, c = a + n + 1, d = c + 1;
            triangles.push_back({a, c, b});
            triangles.push_back({b, c, d});
        }
    std::vector<V> end = start;
    for (std::size_t v = first; v < end.size(); ++v) end[v].z() -= 1.0;

    std::printf("sheet and plate: %zu vertices, %zu triangles; at t = 0 the whole sheet is at least 0.45 above the plate, "
                "at t = 1 at least 0.45 below it: a discrete test at either end sees nothing\n",
                start.size(), triangles.size());

    const cdkit::DeformableCcdResult r = cdkit::self_ccd(start, end, triangles, {}, "sheet and plate");
    std::printf("self_ccd: %zu vertex-face and %zu edge-edge candidates (swept boxes overlap)\n",
                r.stats.vertex_face_candidates, r.stats.edge_edge_candidates);
    if (!r.colliding) {
        std::printf("no contact found: wrong\n");
        return 1;
    }
    const cdkit::CcdContact& c = r.contacts[0];
    std::printf("first contact at t in [%.7f, %.7f]: %s %u against %s %u at (%.4f %.4f %.4f), normal (%.2f %.2f %.2f)%s\n",
                c.ccd.toi, c.ccd.toi_upper, c.vertex_face ? "vertex" : "edge", c.a,
                c.vertex_face ? "triangle" : "edge", c.b, c.ccd.point.x(), c.ccd.point.y(), c.ccd.point.z(),
                c.ccd.normal.x(), c.ccd.normal.y(), c.ccd.normal.z(), c.ccd.proven ? " (proven)" : "");

    // The lowest corner of the sheet (x = −0.5: z = 0.45 at t = 0) reaches the plate at t = 0.45.
    const cdkit::Triangle& plate = triangles[0];
    const cdkit::CcdResult vf = cdkit::vertex_face_ccd(start[first], start[plate[0]], start[plate[1]], start[plate[2]],
                                                       end[first], end[plate[0]], end[plate[1]], end[plate[2]]);
    std::printf("vertex_face_ccd of the sheet's lowest corner and the plate: %s, t in [%.7f, %.7f], %u boxes, %u "
                "Newton steps\n",
                vf.colliding ? "contact" : "no contact", vf.toi, vf.toi_upper, vf.stats.boxes, vf.stats.newton_steps);
    const bool ok = vf.colliding && vf.toi <= 0.45 && vf.toi > 0.449 && r.toi <= 0.45 && r.toi > 0.449;
    return ok ? 0 : 1;
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
}
