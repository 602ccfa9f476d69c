"""cdkit: collision detection for meshes and convex shapes, with numpy at the boundary.

Meshes with bounding volume hierarchies (``MeshModel``, ``collide``, ``distance``), batches over many poses
(``collide_many``, ``distance_many``, ``ray_cast_many``: C++ with TBB, the GIL released), convex shapes (GJK, EPA,
separating planes, closest features, with caller-owned caches), broad phases, ``World``, inner sphere trees,
continuous collision and ray casts. See docs/python.md.

Arrays in: (N,3) float vertices, (M,3) integer faces, poses as 4x4 arrays or ``(R, t)``; bad arrays raise
``ValueError`` before any query runs, ``cdkit.Error`` is the library's error for bad data (files, meshes, World poses).
"""
from ._cdkit import *  # noqa: F401,F403  (the extension module's names are the package's)
from ._cdkit import Error  # noqa: F401  (re-exported explicitly for readers and linters)
from . import _cdkit as _extension

__all__ = [name for name in dir(_extension) if not name.startswith("_")]
__version__ = "0.1.0"
