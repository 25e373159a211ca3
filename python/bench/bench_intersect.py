"""Rays per second of Tracer.intersect from Python, and what the module adds to the library.

For 1M coherent rays (a camera's, in sample order) and 1M random rays, prints the wall time of
the Python call and the time spent inside the library (last_stats['seconds']: intersect_rays
alone); the difference is the module's overhead (array checks, conversion, result arrays).

    /usr/bin/python3 python/bench/bench_intersect.py [scene] [--threads N]
"""
import argparse
import time

import numpy as np

import rtt


def measure(tracer, origins, directions, threads, reps):
    best = None
    for _ in range(reps):
        start = time.perf_counter()
        tracer.intersect(origins, directions, threads=threads)
        wall = time.perf_counter() - start
        inside = tracer.last_stats["seconds"]
        if best is None or wall < best[0]:
            best = (wall, inside)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", default="room")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--reps", type=int, default=3)
    args = parser.parse_args()

    scene = rtt.load(args.scene)
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
    print(f"{'rays':10} {'kind':8} {'Mrays/s':>8} {'library s':>10} {'python s':>9} {'overhead':>9}")
    for label, (o, d) in [("coherent", coherent), ("random", random)]:
        for kind in ["packet", "rtt"]:
            wall, inside = measure(scene.tracer(kind), o, d, args.threads, args.reps)
            print(f"{label:10} {kind:8} {len(d) / wall * 1e-6:8.2f} {inside:10.3f} {wall:9.3f} "
                  f"{(wall - inside) / wall * 100:8.1f}%")


if __name__ == "__main__":
    main()
