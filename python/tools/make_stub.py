#!/usr/bin/env python3
"""Writes python/cdkit/__init__.pyi from the built module: every function, class, property and enum member with
the signatures pybind11 records, the arguments the bindings take as `object` typed by their role (poses, arrays,
shapes, caches, requests), and the first docstring line as a comment-free docstring. Run after changing bindings:

  PYTHONPATH=build-py/python /usr/bin/python3 python/tools/make_stub.py python/cdkit/__init__.pyi

python/tests/test_stubs.py checks that the stub covers every bound name.
"""
import inspect
import re
import sys

import cdkit
from cdkit import _cdkit as ext

POSE_ARGS = re.compile(r"^(pose(_[ab]|_mesh|_shape)?|([ab]|mesh|shape)_(start|end)|poses_[ab])$")
ARRAY_ARGS = {"vertices", "faces", "points", "origins", "directions", "lo", "hi", "half_extents", "radii",
              "direction", "translation", "rotation", "reference_a", "reference_b", "origin", "p_t0", "a_t0", "b_t0",
              "c_t0", "p_t1", "a_t1", "b_t1", "c_t1", "a0_t0", "a1_t0", "b0_t0", "b1_t0", "a0_t1", "a1_t1", "b0_t1",
              "b1_t1"}
CACHES = {"gjk_intersect": "GjkCache", "gjk_distance": "GjkCache", "gjk_distance_within": "GjkCache",
          "separating_plane_intersect": "SeparatingPlaneCache",
          "closest_features": "ClosestFeatureCache", "contact_manifold": "ManifoldCache"}
SHAPE_FUNCS = {"gjk_intersect", "gjk_distance", "gjk_distance_within", "penetration", "separating_plane_intersect",
               "convex_toi",
               "mesh_convex_collide", "mesh_convex_distance", "mesh_convex_penetration", "mesh_convex_toi",
               "convex_ray_cast", "contact_manifold"}
REQUESTS = {"collide": "CollisionRequest", "collide_brute_force": "CollisionRequest", "distance": "DistanceRequest",
            "convex_toi": "ToiRequest", "vertex_face_ccd": "CcdRequest", "edge_edge_ccd": "CcdRequest",
            "mesh_ccd": "DeformableCcdRequest", "DeformableCcdRequest": "CcdRequest",
            "mesh_convex_collide": "MeshConvexRequest", "mesh_convex_distance": "DistanceRequest",
            "mesh_convex_penetration": "MeshConvexRequest", "mesh_convex_toi": "ToiRequest", "mesh_toi": "ToiRequest",
            "convex_ray_cast": "ConvexRayRequest", "contact_manifold": "ManifoldRequest"}
SETTINGS = {"gjk_intersect": "GjkSettings", "gjk_distance": "GjkSettings", "gjk_distance_within": "GjkSettings",
            "penetration": "EpaSettings",
            "separating_plane_intersect": "SeparatingPlaneSettings",
            "closest_features": "ClosestFeatureSettings"}


def clean(t):
    t = t.replace("cdkit._cdkit.", "")
    t = re.sub(r"numpy\.ndarray\[[^\]]*\]", "np.ndarray", t)
    t = t.replace("numpy.ndarray", "np.ndarray")
    t = re.sub(r"\bList\[", "list[", t)
    return t


def arg_type(func, name, t, default):
    t = clean(t)
    if t != "object":
        return t
    if POSE_ARGS.match(name):
        return "Pose | None" if not name.startswith("poses") else "ArrayLike | Pose | None"
    if name in ARRAY_ARGS:
        return "ArrayLike"
    if name == "cache":
        return f"{CACHES.get(func, 'object')} | None"
    if name == "settings":
        return f"{SETTINGS.get(func, 'object')} | None"
    if name in ("request", "primitive"):
        return f"{REQUESTS.get(func, 'object')} | None"
    if name in ("a", "b", "shape") and (func in SHAPE_FUNCS or func == "World.add"):
        return "Shape" if func != "World.add" else "Sphere | Box | Capsule | ConvexPolyhedron | MeshModel"
    if name == "bv":
        return 'BV | str'
    if name == "split":
        return "SplitStrategy | None"
    if name == "options":
        return "WorldOptions | None"
    return "Any"


SIG = re.compile(r"^(\w*)\((.*)\)\s*->\s*(.+)$")


def split_args(s):
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def signatures(obj):
    doc = obj.__doc__ or ""
    sigs, text = [], []
    for line in doc.splitlines():
        m = re.match(r"^(?:\d+\. )?(\w*\(.*\)\s*->\s*.+)$", line.strip())
        if m and SIG.match(m.group(1)):
            sigs.append(SIG.match(m.group(1)).groups())
        elif line.strip() and not line.startswith("Overloaded function"):
            text.append(line.strip())
    return sigs, (text[0] if text else "")


def render_def(qual, name, sig, indent, is_method, static=False, overload=False):
    _, args, ret = sig
    parts = []
    for k, a in enumerate(split_args(args)):
        if ":" not in a:
            parts.append(a)
            continue
        n, rest = a.split(":", 1)
        n = n.strip()
        if "=" in rest:
            t, d = rest.split("=", 1)
            d = d.strip()
            if not re.match(r"^(-?[\d.e+-]+|True|False|None|'[^']*'|\"[^\"]*\")$", d):
                d = "..."
            t = arg_type(qual, n, t.strip(), d)
            parts.append(f"{n}: {t} = {d}")
        else:
            t = arg_type(qual, n, rest.strip(), None)
            if is_method and k == 0 and not static:
                parts.append("self")
            else:
                parts.append(f"{n}: {t}")
    ret = clean(ret.strip())
    if name == "__init__":
        ret = "None"
    deco = (f"{indent}@overload\n" if overload else "") + (f"{indent}@staticmethod\n" if static else "")
    return f"{deco}{indent}def {name}({', '.join(parts)}) -> {ret}: ..."


def render_function(name, obj, indent="", qual=None, is_method=False, static=False):
    sigs, text = signatures(obj)
    out = []
    for sig in sigs:
        out.append(render_def(qual or name, name, sig, indent, is_method, static, overload=len(sigs) > 1))
    if text and out:
        out[-1] = out[-1][:-4] + f'\n{indent}    """{text}"""'
    return out


def render_class(name, cls):
    base = cls.__mro__[1].__name__ if cls.__mro__[1] is not object and cls.__mro__[1].__module__.startswith("cdkit") else ""
    lines = [f"class {name}{'(' + base + ')' if base else ''}:"]
    if cls.__doc__:
        first = cls.__doc__.strip().splitlines()[0]
        lines.append(f'    """{first}"""')
    is_enum = hasattr(cls, "__members__")
    if is_enum:
        for member in cls.__members__:
            lines.append(f"    {member}: ClassVar[{name}]")
        lines.append("    name: str")
        lines.append("    value: int")
        lines.append("    def __init__(self, value: int) -> None: ...")
        lines.append("    def __int__(self) -> int: ...")
        lines.append("    __members__: ClassVar[dict[str, " + name + "]]")
        return lines
    for attr, val in cls.__dict__.items():
        if attr.startswith("_") and attr not in ("__init__", "__len__", "__bool__"):
            continue
        if isinstance(val, property):
            sigs, text = signatures(val.fget)
            ret = clean(sigs[0][2]) if sigs else "Any"
            if val.fset is None:
                lines.append("    @property")
                lines.append(f"    def {attr}(self) -> {ret}: ...")
            else:
                lines.append(f"    {attr}: {ret}")
        elif isinstance(val, staticmethod) or type(val).__name__ == "staticmethod":
            lines += render_function(attr, val.__func__, "    ", f"{name}.{attr}", True, static=True)
        elif callable(val):
            lines += render_function(attr, val, "    ", f"{name}.{attr}", True)
    if len(lines) == 1:
        lines.append("    ...")
    return lines


def main(path):
    out = ['"""Type stubs of the cdkit module (generated by python/tools/make_stub.py from the built extension)."""',
           "from typing import Any, ClassVar, Sequence, Tuple, Union, overload", "",
           "import numpy as np", "import numpy.typing as npt", "",
           "ArrayLike = npt.ArrayLike",
           "Pose = Union[npt.ArrayLike, Tuple[npt.ArrayLike, npt.ArrayLike]]",
           "\"\"\"A 4x4 array (bottom row 0 0 0 1) or a pair (R, t); None where accepted: the identity.\"\"\"", ""]
    names = sorted(n for n in dir(ext) if not n.startswith("_"))
    classes = [n for n in names if isinstance(getattr(ext, n), type)]
    funcs = [n for n in names if n not in classes]
    # Base classes first.
    ordered = sorted(classes, key=lambda n: (len(getattr(ext, n).__mro__), n))
    out += ["class Error(RuntimeError):", '    """Raised for bad data from outside (files, meshes, World poses and ids)."""', ""]
    for n in ordered:
        if n == "Error":
            continue
        out += render_class(n, getattr(ext, n)) + [""]
    out.append("Shape = Union[Sphere, Box, Capsule, Cylinder, Cone, Ellipsoid, ConvexTriangle, ConvexPolyhedron]")
    out.append("")
    for n in funcs:
        out += render_function(n, getattr(ext, n)) + [""]
    text = "\n".join(out).rstrip() + "\n"
    with open(path, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "python/cdkit/__init__.pyi")
