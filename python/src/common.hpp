#pragma once
// Shared by the binding units: numpy checks at the boundary (shape, dtype, finite values: ValueError before any
// cdkit code runs), poses from 4×4 arrays or (R, t), results to arrays, and the mesh-model and shape handles the
// units pass between them.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cdkit/bv/aabb.hpp>
#include <cdkit/bv/kdop.hpp>
#include <cdkit/bv/obb.hpp>
#include <cdkit/bv/rss.hpp>
#include <cdkit/bv/sphere.hpp>
#include <cdkit/bvh/mesh_model.hpp>
#include <cdkit/core/distance_result.hpp>
#include <cdkit/core/math.hpp>
#include <cdkit/core/mesh.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace py = pybind11;

namespace cdkit::python {

using Pose = Transform<double>;
using V3 = Vec3<double>;

// ---- input checks ---------------------------------------------------------------------------------------
/// `obj` as a C-contiguous float64 array after checking that its dtype is a real number type (float, or int for
/// coordinates given as integers) and its shape matches `shape` (-1: any extent). `name` is what the error
/// calls the argument.
py::array_t<double, py::array::c_style | py::array::forcecast> real_array(py::handle obj, const char* name,
                                                                          std::initializer_list<py::ssize_t> shape,
                                                                          bool check_finite = true);
/// The same for index arrays (integer dtype only), as int64.
py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> index_array(py::handle obj, const char* name,
                                                                                 std::initializer_list<py::ssize_t> shape);
/// A 3-vector (any sequence or array of 3 finite reals).
V3 vec3(py::handle obj, const char* name);
/// A list of points from an (N,3) array.
std::vector<V3> points(py::handle obj, const char* name);
/// A pose: None (identity), a 4×4 array (bottom row 0 0 0 1), or a pair (R, t) of a 3×3 and a 3-vector. Finite
/// entries are checked here; whether R is a rotation is the query's check (status invalid_pose), as in C++.
Pose pose(py::handle obj, const char* name);
/// N poses from an (N,4,4) array, or one 4×4 (or (R, t), or None) repeated `n` times when n > 0.
std::vector<Pose> poses(py::handle obj, const char* name, std::size_t n = 0);
/// A mesh from (N,3) vertices and (M,3) faces: at least one face, indices in [0, N).
TriangleMesh<double> mesh_from_arrays(py::handle vertices, py::handle faces, const std::string& source);

// ---- outputs --------------------------------------------------------------------------------------------
py::array_t<double> to_array(const V3& v);
py::array_t<double> to_array(const Pose& p);  ///< 4×4
py::array_t<double> to_array(const std::vector<V3>& v);  ///< (N,3)
py::array_t<std::int64_t> to_array(const std::vector<Triangle>& t);  ///< (M,3)

// ---- mesh models ----------------------------------------------------------------------------------------
enum class BV { aabb, obb, rss, kdop18, sphere };
const char* bv_name(BV b);
using ModelVar = std::variant<std::shared_ptr<const MeshModel<Aabb<double>>>, std::shared_ptr<const MeshModel<Obb<double>>>,
                              std::shared_ptr<const MeshModel<Rss<double>>>,
                              std::shared_ptr<const MeshModel<Kdop<double, 18>>>,
                              std::shared_ptr<const MeshModel<BoundingSphere<double>>>>;
/// Python's MeshModel: one class for every BV type (chosen by `bv`); queries pair two models of the same type.
struct PyMeshModel {
    ModelVar model;
    BV bv = BV::obb;
    const TriangleMesh<double>& mesh() const {
        return std::visit([](const auto& m) -> const TriangleMesh<double>& { return m->mesh(); }, model);
    }
    std::shared_ptr<const TriangleMesh<double>> mesh_ptr() const {
        return std::visit([](const auto& m) { return m->mesh_ptr(); }, model);
    }
};

/// f(model) with the concrete MeshModel<BV>.
template <class F> decltype(auto) visit_model(const PyMeshModel& a, F&& f) {
    return std::visit([&](const auto& pa) -> decltype(auto) { return f(*pa); }, a.model);
}
/// f(model_a, model_b) for two models of the same BV type (ValueError otherwise).
template <class F> decltype(auto) visit_pair(const PyMeshModel& a, const PyMeshModel& b, F&& f) {
    if (a.bv != b.bv)
        throw py::value_error(std::string("both models must use the same bounding volume type (a: ") + bv_name(a.bv) +
                              ", b: " + bv_name(b.bv) + ")");
    return std::visit(
        [&](const auto& pa) -> decltype(auto) {
            using Ptr = std::decay_t<decltype(pa)>;
            return f(*pa, *std::get<Ptr>(b.model));
        },
        a.model);
}


// ---- convex shapes --------------------------------------------------------------------------------------
using Polyhedron = ConvexPolyhedron<double>;
using ShapeVar = std::variant<const Sphere<double>*, const Box<double>*, const Capsule<double>*, const Cylinder<double>*,
                              const Cone<double>*, const Ellipsoid<double>*, const ConvexTriangle<double>*,
                              const Polyhedron*>;
/// The support-mapped shape behind a Python shape object (TypeError for anything else).
ShapeVar shape_of(py::handle obj, const char* name);

// ---- units ----------------------------------------------------------------------------------------------
void init_core(py::module_& m);
void init_mesh(py::module_& m);
void init_batch(py::module_& m);
void init_convex(py::module_& m);
void init_convex_cached(py::module_& m);
void init_world(py::module_& m);
void init_ist(py::module_& m);
void init_ccd(py::module_& m);
void init_mesh_convex(py::module_& m);
void init_mesh_convex_ccd(py::module_& m);
void init_manifold(py::module_& m);
void init_mesh_depth(py::module_& m);

/// A DistanceRequest from Python's keywords, checked (ValueError naming the fields), as DistanceRequest() and
/// distance_many() take them.
inline DistanceRequest<double> distance_request(double rel_err, double abs_err, double max_distance) {
    DistanceRequest<double> r;
    r.rel_err = rel_err;
    r.abs_err = abs_err;
    r.max_distance = max_distance;
    if (!cdkit::detail::distance_request_is_valid(r))
        throw py::value_error("rel_err and abs_err must be finite and >= 0, max_distance >= 0 (inf: no bound)");
    return r;
}

}  // namespace cdkit::python
