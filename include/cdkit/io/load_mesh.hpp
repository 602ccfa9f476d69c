#pragma once
/// \file Mesh import through assimp (OBJ, STL, PLY, OFF, glTF, COLLADA, 3DS, … — whatever assimp reads).

#include "cdkit/core/mesh.hpp"

#include <cstddef>
#include <string>

namespace cdkit {

struct LoadOptions {
    /// Join vertices with identical coordinates, so that shared edges are shared indices (STL and some
    /// OBJ/PLY exporters write each face's corners separately). The join is exact (bit-identical
    /// positions, see join_identical_vertices); nearly equal vertices stay apart. When false, assimp's
    /// OBJ and STL readers give three vertices per triangle.
    bool join_vertices = true;
    /// Polygons with more than three corners are triangulated; points and lines are dropped. When the file
    /// holds no triangle at all, load_mesh raises Error. When false, polygons with more than three corners
    /// are dropped too.
    bool triangulate = true;
};

/// Loads every mesh of the file's scene, with node transforms applied, into one TriangleMesh in double.
/// Throws cdkit::Error naming the file for: a missing or unreadable file, a format assimp cannot parse,
/// NaN/Inf coordinates, out-of-range indices, and a scene without triangles. Never crashes on bad bytes.
///
/// Before assimp sees them, PLY, OFF and binary STL files are checked against the counts their headers
/// declare (assimp allocates what a header claims, and its OFF reader silently clamps bad indices).
/// Side files that a format names (OBJ materials, glTF buffers, …) are opened only when they are
/// regular files. Vertex indices are 32-bit: a scene with 2^32 vertices or more is rejected. assimp's
/// DefaultLogger is left as the application set it (assimp logs nothing unless one is created).
[[nodiscard]] TriangleMesh<double> load_mesh(const std::string& path, const LoadOptions& options = {});

/// The same from bytes in memory; `format_hint` is a file extension such as "obj" or "stl" (assimp's
/// hint; a leading dot is ignored), `name` is what errors call the source. Never reads a file: side files
/// that the data names are treated as missing.
[[nodiscard]] TriangleMesh<double> load_mesh_from_memory(const void* data, std::size_t size,
                                                         const std::string& format_hint,
                                                         const LoadOptions& options = {},
                                                         const std::string& name = "<memory>");

}  // namespace cdkit
