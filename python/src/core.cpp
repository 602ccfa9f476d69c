// The boundary (array checks, poses), cdkit.Error, the status enums, load_mesh.
#include "common.hpp"

#include <cdkit/core/contact_mode.hpp>
#include <cdkit/core/error.hpp>
#include <cdkit/core/status.hpp>
#include <cdkit/io/load_mesh.hpp>

#include <cmath>
#include <sstream>

namespace cdkit::python {

namespace {
std::string shape_text(const py::array& a) {
    std::ostringstream s;
    s << "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}
std::string wanted_text(std::initializer_list<py::ssize_t> shape) {
    std::ostringstream s;
    s << "(";
    std::size_t i = 0;
    for (py::ssize_t e : shape) s << (i++ ? ", " : "") << (e < 0 ? std::string("N") : std::to_string(e));
    s << (shape.size() == 1 ? ",)" : ")");
    return s.str();
}
py::array any_array(py::handle obj, const char* name) {
    if (obj.is_none()) throw py::value_error(std::string(name) + ": expected an array, got None");
    py::array a = py::array::ensure(obj);
    if (!a) throw py::value_error(std::string(name) + ": not convertible to an array");
    return a;
}
void check_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape) {
    bool ok = a.ndim() == py::ssize_t(shape.size());
    std::size_t i = 0;
    for (py::ssize_t e : shape) {
        if (!ok) break;
        ok = e < 0 || a.shape(py::ssize_t(i)) == e;
        ++i;
    }
    if (!ok)
        throw py::value_error(std::string(name) + ": expected shape " + wanted_text(shape) + ", got " + shape_text(a));
}
}  // namespace

py::array_t<double, py::array::c_style | py::array::forcecast> real_array(py::handle obj, const char* name,
                                                                          std::initializer_list<py::ssize_t> shape,
                                                                          bool check_finite) {
    py::array a = any_array(obj, name);
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::value_error(std::string(name) + ": expected a float (or integer) array, got dtype " +
                              std::string(py::str(a.dtype())));
    check_shape(a, name, shape);
    auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!d) throw py::value_error(std::string(name) + ": not convertible to float64");
    if (check_finite) {
        const double* p = d.data();
        for (py::ssize_t i = 0; i < d.size(); ++i)
            if (!std::isfinite(p[i]))
                throw py::value_error(std::string(name) + ": entry " + std::to_string(i) + " is NaN or infinite");
    }
    return d;
}

py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> index_array(py::handle obj, const char* name,
                                                                                 std::initializer_list<py::ssize_t> shape) {
    py::array a = any_array(obj, name);
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw py::value_error(std::string(name) + ": expected an integer array, got dtype " + std::string(py::str(a.dtype())));
    check_shape(a, name, shape);
    auto d = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!d) throw py::value_error(std::string(name) + ": not convertible to int64");
    return d;
}

V3 vec3(py::handle obj, const char* name) {
    const auto a = real_array(obj, name, {3});
    return V3(a.at(0), a.at(1), a.at(2));
}

std::vector<V3> points(py::handle obj, const char* name) {
    const auto a = real_array(obj, name, {-1, 3});
    std::vector<V3> out(std::size_t(a.shape(0)));
    const double* p = a.data();
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = V3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    return out;
}

namespace {
Pose pose_from_4x4(const double* p, const char* name, std::size_t index, bool batch) {
    if (p[12] != 0 || p[13] != 0 || p[14] != 0 || p[15] != 1)
        throw py::value_error(std::string(name) + (batch ? " [" + std::to_string(index) + "]" : std::string()) +
                              ": the bottom row of a 4x4 pose must be (0, 0, 0, 1)");
    Pose t;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) t.R(r, c) = p[4 * r + c];
        t.t[r] = p[4 * r + 3];
    }
    return t;
}
}  // namespace

Pose pose(py::handle obj, const char* name) {
    if (obj.is_none()) return Pose{};
    if (py::isinstance<py::tuple>(obj) || py::isinstance<py::list>(obj)) {
        const auto seq = py::reinterpret_borrow<py::sequence>(obj);
        if (seq.size() == 2) {
            const auto R = real_array(seq[0], name, {3, 3});
            Pose t;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) t.R(r, c) = R.at(r, c);
            t.t = vec3(seq[1], name);
            return t;
        }
    }
    const auto a = real_array(obj, name, {4, 4});
    return pose_from_4x4(a.data(), name, 0, false);
}

std::vector<Pose> poses(py::handle obj, const char* name, std::size_t n) {
    if (n > 0) {
        // One pose for every entry?
        bool single = obj.is_none() || py::isinstance<py::tuple>(obj);
        if (!single) {
            py::array a = any_array(obj, name);
            single = a.ndim() == 2;
        }
        if (single) return std::vector<Pose>(n, pose(obj, name));
    }
    const auto a = real_array(obj, name, {-1, 4, 4});
    std::vector<Pose> out(std::size_t(a.shape(0)));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = pose_from_4x4(a.data() + 16 * i, name, i, true);
    return out;
}

namespace {
/// `obj` as a C-contiguous array of exactly T when it already is one (no conversion, no copy), else empty.
template <class T> py::array_t<T, py::array::c_style> exact_array(py::handle obj) {
    if (!py::isinstance<py::array_t<T, py::array::c_style>>(obj)) return {};
    return py::reinterpret_borrow<py::array_t<T, py::array::c_style>>(obj);
}

/// The mesh's vertices read straight from an (N,3) array of S (the model copies them once, into its own mesh).
template <class S> void read_vertices(const S* p, std::int64_t n, TriangleMesh<double>& m) {
    m.vertices.resize(std::size_t(n));
    for (std::int64_t i = 0; i < 3 * n; ++i)
        if (!std::isfinite(double(p[i])))
            throw py::value_error("vertices: entry " + std::to_string(i) + " is NaN or infinite");
    for (std::int64_t i = 0; i < n; ++i)
        m.vertices[std::size_t(i)] = V3(double(p[3 * i]), double(p[3 * i + 1]), double(p[3 * i + 2]));
}

/// The triangles from an (M,3) integer array of I, every index checked against the n vertices.
template <class I> void read_triangles(const I* p, std::size_t count, std::int64_t n, TriangleMesh<double>& m) {
    m.triangles.resize(count);
    for (std::size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            const std::int64_t x = std::int64_t(p[3 * i + std::size_t(k)]);
            if (x < 0 || x >= n)
                throw py::value_error("faces: triangle " + std::to_string(i) + " has vertex index " + std::to_string(x) +
                                      ", out of range for " + std::to_string(n) + " vertices");
            m.triangles[i][std::size_t(k)] = Index(x);
        }
}
}  // namespace

TriangleMesh<double> mesh_from_arrays(py::handle vertices, py::handle faces, const std::string& source) {
    TriangleMesh<double> m;
    m.source = source;
    // float32 / float64 vertices and int32 / int64 faces in C order are read in place; anything else is converted
    // (and checked) to float64 / int64 first.
    std::int64_t n = 0;
    if (const auto v32 = exact_array<float>(vertices); v32 && v32.ndim() == 2 && v32.shape(1) == 3) {
        n = v32.shape(0);
        read_vertices(v32.data(), n, m);
    } else {
        const auto v = real_array(vertices, "vertices", {-1, 3}, false);  // read_vertices checks finiteness
        n = v.shape(0);
        read_vertices(v.data(), n, m);
    }
    if (const auto f32 = exact_array<std::int32_t>(faces); f32 && f32.ndim() == 2 && f32.shape(1) == 3) {
        if (f32.shape(0) == 0) throw py::value_error("faces: the mesh has no triangles");
        read_triangles(f32.data(), std::size_t(f32.shape(0)), n, m);
    } else {
        const auto f = index_array(faces, "faces", {-1, 3});
        if (f.shape(0) == 0) throw py::value_error("faces: the mesh has no triangles");
        read_triangles(f.data(), std::size_t(f.shape(0)), n, m);
    }
    return m;
}

py::array_t<double> to_array(const V3& v) {
    py::array_t<double> a(3);
    for (int k = 0; k < 3; ++k) a.mutable_at(k) = v[k];
    return a;
}
py::array_t<double> to_array(const Pose& p) {
    py::array_t<double> a({4, 4});
    auto w = a.mutable_unchecked<2>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) w(r, c) = r < 3 ? (c < 3 ? p.R(r, c) : p.t[r]) : (c == 3 ? 1.0 : 0.0);
    return a;
}
py::array_t<double> to_array(const std::vector<V3>& v) {
    py::array_t<double> a({py::ssize_t(v.size()), py::ssize_t(3)});
    double* p = a.mutable_data();
    for (std::size_t i = 0; i < v.size(); ++i)
        for (int k = 0; k < 3; ++k) p[3 * i + std::size_t(k)] = v[i][k];
    return a;
}
py::array_t<std::int64_t> to_array(const std::vector<Triangle>& t) {
    py::array_t<std::int64_t> a({py::ssize_t(t.size()), py::ssize_t(3)});
    std::int64_t* p = a.mutable_data();
    for (std::size_t i = 0; i < t.size(); ++i)
        for (int k = 0; k < 3; ++k) p[3 * i + std::size_t(k)] = t[i][std::size_t(k)];
    return a;
}

const char* bv_name(BV b) {
    switch (b) {
        case BV::aabb: return "aabb";
        case BV::obb: return "obb";
        case BV::rss: return "rss";
        case BV::kdop18: return "kdop18";
        case BV::sphere: return "sphere";
    }
    return "?";
}

void init_core(py::module_& m) {
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    error.doc() = "Raised for bad data from outside (files, meshes, World poses and ids): the message names the "
                  "source, the element and the reason (cdkit::Error).";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            error(e.what());
        }
    });
    // A failed CDKIT_ASSERT (an internal invariant, e.g. in a tree build) must not abort the interpreter: in the
    // module it raises cdkit.Error naming the check. Its call sites are construction paths, which may throw.
    set_assert_handler([](const char* expr, const char* msg, const char* file, int line) {
        throw Error(std::string(file) + ":" + std::to_string(line), std::string("internal check ") + expr, msg);
    });
    m.def("_fail_assert_for_test", [] { CDKIT_ASSERT(false, "a test of the assert handler"); },
          "Fails a CDKIT_ASSERT, to test that it raises cdkit.Error (internal).");

    py::enum_<QueryStatus>(m, "QueryStatus", "Outcome of a mesh, IST, CCD or ray query's input check.")
        .value("ok", QueryStatus::ok)
        .value("invalid_pose", QueryStatus::invalid_pose)
        .value("invalid_input", QueryStatus::invalid_input);
    py::enum_<GjkStatus>(m, "GjkStatus", "Outcome of a convex query: the class of the answer.")
        .value("separated", GjkStatus::separated)
        .value("touching", GjkStatus::touching)
        .value("intersecting", GjkStatus::intersecting)
        .value("max_iterations", GjkStatus::max_iterations)
        .value("degenerate", GjkStatus::degenerate);
    py::enum_<ContactMode>(m, "ContactMode", "How many contacts a query reports.")
        .value("first", ContactMode::first)
        .value("all", ContactMode::all);
    py::enum_<BV>(m, "BV", "The bounding volume type of a MeshModel's tree.")
        .value("aabb", BV::aabb)
        .value("obb", BV::obb)
        .value("rss", BV::rss)
        .value("kdop18", BV::kdop18)
        .value("sphere", BV::sphere);
    m.def("is_colliding", &is_colliding, py::arg("status"), "Touching or intersecting.");
    m.def("to_string", py::overload_cast<QueryStatus>(&to_string), py::arg("status"));
    m.def("to_string", py::overload_cast<GjkStatus>(&to_string), py::arg("status"));

    m.def(
        "load_mesh",
        [](const std::string& path, bool join_vertices, bool triangulate) {
            LoadOptions o;
            o.join_vertices = join_vertices;
            o.triangulate = triangulate;
            TriangleMesh<double> mesh;
            {
                py::gil_scoped_release nogil;
                mesh = load_mesh(path, o);
            }
            return py::make_tuple(to_array(mesh.vertices), to_array(mesh.triangles));
        },
        py::arg("path"), py::arg("join_vertices") = true, py::arg("triangulate") = true,
        "Loads a mesh file (OBJ, STL, PLY, OFF, glTF, ... through assimp) as (vertices (N,3) float64, faces (M,3) "
        "int64). Raises cdkit.Error naming the file for a missing, unreadable or bad file.");
    m.def(
        "pose",
        [](py::object rotation, py::object translation) {
            Pose p;
            if (!rotation.is_none()) {
                const auto R = real_array(rotation, "rotation", {3, 3});
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) p.R(r, c) = R.at(r, c);
            }
            if (!translation.is_none()) p.t = vec3(translation, "translation");
            return to_array(p);
        },
        py::arg("rotation") = py::none(), py::arg("translation") = py::none(),
        "A 4x4 pose array from a 3x3 rotation and a translation (either may be None: identity / zero).");
    m.def(
        "pose_is_usable", [](py::object p) { return pose_is_usable(pose(p, "pose")); }, py::arg("pose"),
        "True when the pose is a finite rigid motion to within sqrt(eps) (the check every query makes).");
}

}  // namespace cdkit::python
