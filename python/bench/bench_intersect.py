"""Rays per second of Tracer.intersect and Tracer.visible from Python, against Embree's single rays.

For 1M coherent rays (a camera's, in sample order) and 1M random rays (origins in the middle 90 %
of the scene's box, towards random points of it), prints each kind's rate, the time spent inside
the library (last_stats['seconds']: the C++ batch call alone) and the module's overhead (array
checks, conversion, result arrays), and the kind's speed over `embree1`'s (Embree's rtcIntersect1 /
rtcOccluded1 per ray, as trimesh, Open3D and embreex call it) where the build has Embree.

    /usr/bin/python3 python/bench/bench_intersect.py [scene] [--threads N] [--kinds rtt,bvh,bvh-high,embree1]
"""
import argparse
import time

import numpy as np

import rtt


def measure(call, reps):
    """Best wall time of `reps` calls, and the library's own seconds in that call."""
    best = None
    for _ in range(reps):
        start = time.perf_counter()
        inside = call()
        wall = time.perf_counter() - start
        if best is None or wall < best[0]:
            best = (wall, inside)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", default="room", help="a built-in scene or a scene file")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--kinds", default="rtt,bvh,bvh-high,embree1", help="comma-separated tracer kinds")
    args = parser.parse_args()

    scene = rtt.load(args.scene)
    kinds = [k for k in args.kinds.split(",") if k in rtt.tracer_kinds()]
    lo, hi = scene.bounds
    origin, dirs = rtt.camera_rays([*(lo + (hi - lo) * [0.9, 0.6, 0.9]), *((lo + hi) / 2), 0, 1, 0, 60],
                                   1000, 1000)
    coherent = (origin, dirs.reshape(-1, 3))
    rng = np.random.default_rng(1)
    org = (lo + (hi - lo) * rng.uniform(0.05, 0.95, (1_000_000, 3))).astype(np.float32)
    tgt = (lo + (hi - lo) * rng.uniform(0.0, 1.0, (1_000_000, 3))).astype(np.float32)
    random = (org, tgt - org)

    print(f"rtt {rtt.__version__}, scene {args.scene} ({scene.triangle_count} triangles), "
          f"{args.threads} thread(s), best of {args.reps}")
    print(f"{'rays':10} {'query':9} {'kind':8} {'Mrays/s':>8} {'library s':>10} {'python s':>9} "
          f"{'overhead':>9} {'/ embree1':>9}")
    tracers = {kind: scene.tracer(kind) for kind in kinds}
    for label, (o, d) in [("coherent", coherent), ("random", random)]:
        for query in ["intersect", "visible"]:
            times = {}
            for kind, tracer in tracers.items():
                method = getattr(tracer, query)

                def call():
                    method(o, d, threads=args.threads)
                    return tracer.last_stats["seconds"]

                times[kind] = measure(call, args.reps)
            for kind, (wall, inside) in times.items():
                ratio = f"{times['embree1'][0] / wall:.2f}x" if "embree1" in times else "-"
                print(f"{label:10} {query:9} {kind:8} {len(d) / wall * 1e-6:8.2f} {inside:10.3f} "
                      f"{wall:9.3f} {(wall - inside) / wall * 100:8.1f}% {ratio:>9}")

if __name__ == "__main__":
    main()
