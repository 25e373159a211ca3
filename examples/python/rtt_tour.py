"""A short tour of rtt from Python: render a scene, see which samples RTT answered from its
relevant lists, and measure RTT against 4-wide packets as antialiasing grows.

    /usr/bin/python3 examples/python/rtt_tour.py [scene] [--out-dir DIR]

Writes DIR/render.ppm, DIR/answered.pgm (white = every sample of the pixel answered by RTT) and,
when matplotlib is installed, DIR/speedup.png.
"""
import argparse
import pathlib

import numpy as np

import rtt


def write_pnm(path, image):
    magic = b"P6" if image.ndim == 3 else b"P5"
    header = b"%s\n%d %d\n255\n" % (magic, image.shape[1], image.shape[0])
    pathlib.Path(path).write_bytes(header + np.ascontiguousarray(image, dtype=np.uint8).tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", default="room")
    parser.add_argument("--out-dir", default=".")
    args = parser.parse_args()
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)

    scene = rtt.load(args.scene)
    print(scene)
    write_pnm(out / "render.ppm", rtt.render(scene, width=320, height=240, aa=2))

    # Which samples RTT answered (the paper's Figure 5b): white = every sample of the pixel.
    tracer, packets = scene.tracer("rtt"), scene.tracer("packet")
    k = 4
    _, _, how = tracer.camera_hits(None, 320, 240, k, answers=True)
    share = (how > 0).reshape(240, k, 320, k).mean(axis=(1, 3))
    write_pnm(out / "answered.pgm", np.round(share * 255))

    # RTT against 4-wide packets on the same camera rays, K = 1..6.
    tracer, packets = scene.tracer("rtt"), scene.tracer("packet")
    rows = []
    for aa in range(1, 7):
        _, tri = tracer.camera_hits(None, 160, 120, aa, threads=1)
        rtt_stats = tracer.last_stats
        _, tri_packets = packets.camera_hits(None, 160, 120, aa, threads=1)
        assert np.array_equal(tri, tri_packets), "rtt and packet disagree"
        speedup = packets.last_stats["seconds"] / rtt_stats["seconds"]
        rows.append((aa, rtt_stats["answered"] / rtt_stats["rays"], speedup))
        print(f"{aa}x{aa}: {rtt_stats['rays']:8d} rays, {100 * rows[-1][1]:5.1f}% answered by RTT, "
              f"rtt/packet {speedup:.2f}x, 0 mismatches")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
        return
    aa, answered, speedup = zip(*rows)
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(aa, speedup, "o-", label="rtt / packet (time)")
    ax.plot(aa, answered, "s--", label="share answered by RTT")
    ax.set_xlabel("antialiasing K (K x K samples per pixel)")
    ax.set_title(f"{scene.name}, 160x120, one thread")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "speedup.png", dpi=120)
    print("wrote", out / "speedup.png")


if __name__ == "__main__":
    main()
