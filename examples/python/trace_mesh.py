"""Load a mesh file, trace rays from numpy, render an image: the three things a Python user
does first with rtt (`pip install .`, README "Python").

    python trace_mesh.py MESH [--out image.ppm]

Prints how many of a grid of rays from above hit the mesh (and checks the exact kinds agree),
then renders the mesh from its default camera into a PPM image.
"""
import argparse
import pathlib

import numpy as np

import rtt


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mesh", help="any format rtt reads: OBJ, PLY, OFF, glTF, STL, ...")
    parser.add_argument("--out", default="mesh.ppm")
    args = parser.parse_args()

    scene = rtt.load(args.mesh)
    lo, hi = scene.bounds
    print(f"{args.mesh}: {scene.triangle_count} triangles, bounds {lo} .. {hi}")

    # A 64 x 64 grid of rays straight down onto the mesh, from above its bounding box.
    xs = np.linspace(lo[0], hi[0], 64, dtype=np.float32)
    zs = np.linspace(lo[2], hi[2], 64, dtype=np.float32)
    gx, gz = np.meshgrid(xs, zs)
    origins = np.stack([gx.ravel(), np.full(gx.size, hi[1] + 1, np.float32), gz.ravel()], axis=1)
    directions = np.tile(np.array([0, -1, 0], np.float32), (len(origins), 1))
    t, tri = scene.tracer("rtt").intersect(origins, directions)
    _, tri_ray = scene.tracer("ray").intersect(origins, directions)
    assert np.array_equal(tri, tri_ray), "rtt and the reference tracer must agree ray for ray"
    print(f"{(tri >= 0).sum()} of {len(tri)} rays hit; nearest hit at t = {t[tri >= 0].min(initial=np.inf):.3f}")

    image = rtt.render(scene, width=320, height=240)
    header = b"P6\n%d %d\n255\n" % (image.shape[1], image.shape[0])
    pathlib.Path(args.out).write_bytes(header + np.ascontiguousarray(image).tobytes())
    print(f"wrote {args.out} ({image.shape[1]}x{image.shape[0]})")


if __name__ == "__main__":
    main()
