#!/usr/bin/env python3
"""The first image as a user gets it: one fresh `rtt render` process per sample.

For each scene and tracer kind, runs `rtt render --scene S --tracer T --size WxH --threads 1
--stats-json F` REPS times, each in a process of its own (so every build pays for fresh memory, as
a user's first image does), and reads from F the kd-tree build, the tracer's setup and the
render's wall time. Their sum is the first image; the table gives the median of each part
and Embree MEDIUM's first image over each kind's (above 1: the kind is faster). `rtt bench
embree` times the same parts inside one warm process; docs/benchmarks.md, "First image", has both.

    bench/first_image.py [--rtt build/rtt] [--reps 3] [--size 1024x768] [--kinds bvh,...]
                         [scenes ...]        # default: room office plants
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def first_image(rtt, scene, kind, size, tmp):
    """Seconds of one fresh render, from its --stats-json: (kd-tree, tracer setup, render wall)."""
    stats = os.path.join(tmp, "stats.json")
    cmd = [rtt, "render", "--scene", scene, "--tracer", kind, "--size", size, "--threads", "1",
           "--quiet", "--stats-json", stats, "-o", os.path.join(tmp, "image.png")]
    try:
        run = subprocess.run(cmd, capture_output=True, text=True, check=False)
    except OSError as e:
        sys.exit(f"first_image: cannot run {rtt}: {e.strerror}")
    if run.returncode != 0:
        sys.exit(f"first_image: {' '.join(cmd)} failed: {run.stderr.strip()}")
    try:
        with open(stats, encoding="utf-8") as f:
            j = json.load(f)
        kd = j["kd_build_seconds"] if j["kd_tree_used"] else 0.0
        return float(kd), float(j["tracer_build_seconds"]), float(j["wall_seconds"])
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"first_image: no statistics from {' '.join(cmd)}: {e}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtt", default="build/rtt")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("--kinds", default="bvh,rtt,embree-medium,embree")
    ap.add_argument("scenes", nargs="*", default=["room", "office", "plants"])
    args = ap.parse_args()
    if args.reps < 1:
        sys.exit("first_image: --reps must be at least 1")
    kinds = args.kinds.split(",")
    print(f"first image, fresh process each, 1 thread, {args.size}, median of {args.reps}; "
          "seconds: kd-tree + setup + render = total, MEDIUM's total / this total")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            runs = {k: [] for k in kinds}
            for _ in range(args.reps):  # kinds alternate, so a busy moment hits all alike
                for k in kinds:
                    runs[k].append(first_image(args.rtt, scene, k, args.size, tmp))
            med = {k: [statistics.median(part) for part in zip(*runs[k])] for k in kinds}
            totals = {k: statistics.median(sum(r) for r in runs[k]) for k in kinds}
            base = totals.get("embree-medium")
            for k in kinds:
                kd, setup, wall = med[k]
                ratio = f"{base / totals[k]:.2f}x" if base else "-"
                print(f"{os.path.basename(scene):12} {k:14} {kd:6.3f} + {setup:6.3f} + {wall:6.3f} = "
                      f"{totals[k]:6.3f}  {ratio}")


if __name__ == "__main__":
    main()
