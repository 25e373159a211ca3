#!/usr/bin/env python3
"""Writes a user-style test mesh for RTT on objects against background (docs/benchmarks.md,
"Objects against background", "Loose rays"): a bumpy sphere of about 200k triangles (OBJ) and
three JSON scenes framing it, `bumpy.json` (about half the image background),
`bumpy_floor.json` (the same object on a large floor) and `bumpy_mirror.json` (the sphere a
mirror on the floor, three grey copies around it).

    python3 bench/make_bumpy.py OUTDIR [--segments 450]
"""
import argparse
import math
import os


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--segments", type=int, default=450, help="around the equator (2 s^2 / 2 triangles)")
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    nu, nv = a.segments, a.segments // 2
    lines = []
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu):
            ph = 2 * math.pi * i / nu
            r = 1 + 0.08 * math.sin(9 * th) * math.sin(11 * ph) + 0.02 * math.sin(37 * th + 3 * ph)
            lines.append("v %.6f %.6f %.6f" % (r * math.sin(th) * math.cos(ph), r * math.cos(th),
                                               r * math.sin(th) * math.sin(ph)))
    for j in range(nv):
        for i in range(nu):
            a0 = j * nu + i + 1
            b0 = j * nu + (i + 1) % nu + 1
            a1, b1 = a0 + nu, b0 + nu
            if j > 0:
                lines.append("f %d %d %d" % (a0, b0, b1))
            if j < nv - 1:
                lines.append("f %d %d %d" % (a0, b1, a1))
    with open(os.path.join(a.outdir, "bumpy.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")
    floor = ('{"vertices": [[-20, -1.1, -20], [20, -1.1, -20], [20, -1.1, 20], '
             '[-20, -1.1, 20]], "triangles": [[0, 2, 1], [0, 3, 2]], "material": "grey"}')
    copies = ['{"path": "bumpy.obj", "material": "grey", "transform": {"translate": [%g, 0, %g]}}'
              % xz for xz in ((-2.5, -1.5), (2.0, -2.5), (-1.5, 2.5))]
    scenes = (("bumpy", "grey", []), ("bumpy_floor", "grey", [floor]),
              ("bumpy_mirror", "mirror", copies + [floor]))
    for name, material, others in scenes:
        meshes = ['{"path": "bumpy.obj", "material": "%s"}' % material] + others
        with open(os.path.join(a.outdir, name + ".json"), "w") as f:
            f.write('{\n  "camera": {"position": [1.7, 1.1, 2.3], "target": [0, -0.1, 0], '
                    '"up": [0, 1, 0], "fovy": 50},\n'
                    '  "materials": [{"name": "grey", "diffuse": [0.7, 0.7, 0.7]},\n'
                    '                {"name": "mirror", "diffuse": [0.05, 0.05, 0.05], '
                    '"specular": [0.9, 0.9, 0.9], "shininess": 200, "mirror": 0.9}],\n'
                    '  "lights": [{"type": "omni", "position": [3, 5, 4], "color": [1, 1, 1], '
                    '"intensity": 40}],\n  "meshes": [\n    ' + ",\n    ".join(meshes) + "\n  ]\n}\n")


if __name__ == "__main__":
    main()
