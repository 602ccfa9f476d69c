// The levels of a bounding volume hierarchy: how fast each BV type and split strategy closes in on the mesh.
// For Aabb, Obb and sphere trees over the bunny, built with the median, SAH and PCA-volume splits, prints per
// level the number of nodes and their summed volume against the mesh's own volume (the lecture's cost
// argument: a traversal's expected cost grows with the volume of the nodes it has to open). With --csv it also
// writes the nodes of the first levels, from which docs/figures/bvh_figures.py draws docs/images/bvh_*.png; with
// --levels-csv the printed table (results/tree_levels.csv, rendered in docs/bvh.md).
// Usage: tree_levels [mesh file] [--csv FILE] [--levels-csv FILE] [--levels N]   (default: data/bunny.obj, 8 levels)
#include <cdkit/cdkit.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {
using namespace cdkit;

/// One node as the CSV and the table see it: a box (an Aabb's axes are the identity) or a ball.
struct NodeShape {
    Vec3<double> center;
    Mat3<double> axes = Mat3<double>::Identity();
    Vec3<double> half;  // a ball: (r, r, r)
    double volume;
};

NodeShape shape_of(const Aabb<double>& b) { return {b.center, Mat3<double>::Identity(), b.half, b.volume()}; }
NodeShape shape_of(const Obb<double>& b) { return {b.center, b.axes, b.half, b.volume()}; }
NodeShape shape_of(const BoundingSphere<double>& b) {
    return {b.center, Mat3<double>::Identity(), Vec3<double>::Constant(b.radius), b.volume()};
}

/// Volume enclosed by a closed, consistently oriented mesh (divergence theorem: signed tetrahedra to the origin).
double mesh_volume(const TriangleMesh<double>& m) {
    double v = 0;
    for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
    return std::abs(v);
}

template <class BV>
void report(const char* bv_name, const char* split_name, SplitStrategy split, const std::shared_ptr<const TriangleMesh<double>>& mesh,
            double mesh_volume, int levels, std::FILE* csv, std::FILE* levels_csv) {
    BuildOptions options;
    options.split = split;
    const MeshModel<BV> model(mesh, options);
    const auto& nodes = model.bvh().nodes();
    std::printf("  %-6s %-10s depth %2zu |", bv_name, split_name, model.bvh().depth());
    std::vector<std::uint32_t> level{0};
    for (int l = 1; l <= levels && !level.empty(); ++l) {
        double volume = 0;
        std::vector<std::uint32_t> next;
        for (std::uint32_t i : level) {
            const NodeShape s = shape_of(nodes[i].bv);
            volume += s.volume;
            if (csv) {
                std::fprintf(csv, "%s,%s,%d,%u", bv_name, split_name, l, i);
                for (int k = 0; k < 3; ++k) std::fprintf(csv, ",%.9g", s.center[k]);
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) std::fprintf(csv, ",%.9g", s.axes(r, c));
                for (int k = 0; k < 3; ++k) std::fprintf(csv, ",%.9g", s.half[k]);
                std::fprintf(csv, "\n");
            }
            if (!nodes[i].is_leaf()) next.insert(next.end(), {nodes[i].first, nodes[i].first + 1});
        }
        std::printf(" %6.2f", volume / mesh_volume);
        if (levels_csv)
            std::fprintf(levels_csv, "%s,%s,%zu,%d,%zu,%.6g\n", bv_name, split_name, model.bvh().depth(), l, level.size(),
                         volume / mesh_volume);
        level.swap(next);
    }
    std::printf("\n");
}
}  // namespace

int main(int argc, char** argv) try {
    const char* path = CDKIT_DEFAULT_MESH;
    const char* csv_path = nullptr;
    const char* levels_csv_path = nullptr;
    int levels = 8;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--csv") == 0 && i + 1 < argc) csv_path = argv[++i];
        else if (std::strcmp(argv[i], "--levels-csv") == 0 && i + 1 < argc) levels_csv_path = argv[++i];
        else if (std::strcmp(argv[i], "--levels") == 0 && i + 1 < argc) levels = std::max(1, std::atoi(argv[++i]));
        else path = argv[i];
    }
    const auto mesh = std::make_shared<const TriangleMesh<double>>(load_mesh(path));
    const double volume = mesh_volume(*mesh);
    if (!(volume > 0)) throw Error(path, "", "the mesh encloses no volume (open or flat): the table relates node volume to it");
    std::FILE* csv = nullptr;
    if (csv_path) {
        csv = std::fopen(csv_path, "w");
        if (!csv) throw Error(csv_path, "", "cannot write the CSV file");
        std::fprintf(csv, "bv,split,level,node,cx,cy,cz,a00,a01,a02,a10,a11,a12,a20,a21,a22,hx,hy,hz\n");
    }
    std::FILE* levels_csv = nullptr;
    if (levels_csv_path) {
        levels_csv = std::fopen(levels_csv_path, "w");
        if (!levels_csv) throw Error(levels_csv_path, "", "cannot write the CSV file");
        // Provenance, as every file under results/ opens (deterministic: no machine or timing in it).
        std::fprintf(levels_csv, "# command: tree_levels %s --levels-csv %s --levels %d\n# mesh: %s, %zu triangles\n",
                     path, levels_csv_path, levels, path, mesh->num_triangles());
        std::fprintf(levels_csv, "bv,split,depth,level,nodes,volume_over_mesh\n");
    }
    std::printf("%s: %zu triangles. Summed node volume per level, in units of the mesh's volume (level 1 = root):\n",
                path, mesh->num_triangles());
    struct Split {
        const char* name;
        SplitStrategy split;
    };
    for (const Split s : {Split{"median", SplitStrategy::median}, Split{"sah", SplitStrategy::sah},
                          Split{"pca_volume", SplitStrategy::pca_volume}}) {
        report<Aabb<double>>("aabb", s.name, s.split, mesh, volume, levels, csv, levels_csv);
        report<Obb<double>>("obb", s.name, s.split, mesh, volume, levels, csv, levels_csv);
        report<BoundingSphere<double>>("sphere", s.name, s.split, mesh, volume, levels, csv, levels_csv);
    }
    if (csv) std::fclose(csv);
    if (levels_csv) std::fclose(levels_csv);
    return 0;
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "tree_levels: %s\n", e.what());
    return 1;
}
