"""rtt: exact visibility for coherent rays -- SAH kd-tree, SIMD packets and relevant triangles
tracing (Dmitriev, Havran, Seidel 2004), from numpy.

    import numpy as np, rtt
    scene = rtt.Scene.from_arrays(vertices, triangles)   # or rtt.load("mesh.obj") / rtt.load("room")
    tracer = scene.tracer("rtt")
    t, tri = tracer.intersect(origins, directions)       # inf / -1 on a miss
    t, tri = tracer.camera_hits([0, 1, 5, 0, 1, 0, 0, 1, 0, 60], 640, 480, aa=2)
    image = rtt.render(scene, width=640, height=480)     # (H, W, 3) uint8
    hits = rtt.read_hits("room.rtth")                    # `rtt render --hits`: (H, W, K, K)

python/README.md documents every call.
"""
from ._rtt import (Scene, Tracer, __version__, builtin_scenes, camera_rays, isa, limit_isa, load,
                   render, tracer_kinds)
from .buffers import read_hits, read_shadows

__all__ = [
    "Scene", "Tracer", "__version__", "builtin_scenes", "camera_rays", "isa", "limit_isa", "load",
    "read_hits", "read_shadows", "render", "tracer_kinds"
]
