"""The Python module against the library: shapes, dtypes and bad input, agreement between
tracer kinds and with the command line's buffers, thread safety, a 1M-ray batch."""
import concurrent.futures
import pathlib
import struct
import subprocess
import zlib

import numpy as np
import pytest

import rtt

EXACT_KINDS = [k for k in rtt.tracer_kinds() if not k.startswith("embree")]
EMBREE_KINDS = [k for k in rtt.tracer_kinds() if k.startswith("embree")]


def test_installed_module_is_used():
    # The test command runs against the installed package, not the build folder.
    assert "dist-packages" in rtt.__file__ or "site-packages" in rtt.__file__, rtt.__file__
    assert rtt.__version__.count(".") == 2
    assert {"ray", "packet", "rtt"} <= set(rtt.tracer_kinds())


def box_scene(n=8):
    """A grid floor and a box on it, n x n quads per face."""
    g = np.linspace(-1.0, 1.0, n + 1)
    verts, tris = [], []

    def grid(origin, du, dv):
        base = len(verts)
        for b in g:
            for a in g:
                verts.append(np.asarray(origin) + (a + 1) / 2 * np.asarray(du) + (b + 1) / 2 * np.asarray(dv))
        for j in range(n):
            for i in range(n):
                k = base + j * (n + 1) + i
                tris.append((k, k + 1, k + n + 2))
                tris.append((k, k + n + 2, k + n + 1))

    grid((-3, 0, -3), (6, 0, 0), (0, 0, 6))
    for o, du, dv in [((-1, 0, -1), (2, 0, 0), (0, 1, 0)), ((-1, 0, 1), (2, 0, 0), (0, 1, 0)),
                      ((-1, 0, -1), (0, 0, 2), (0, 1, 0)), ((1, 0, -1), (0, 0, 2), (0, 1, 0)),
                      ((-1, 1, -1), (2, 0, 0), (0, 0, 2))]:
        grid(o, du, dv)
    return np.array(verts, dtype=np.float64), np.array(tris, dtype=np.int32)


def random_rays(n, seed=1):
    rng = np.random.default_rng(seed)
    org = rng.uniform(-4, 4, (n, 3)).astype(np.float32)
    org[:, 1] = rng.uniform(0.5, 4, n)
    target = rng.uniform(-1.5, 1.5, (n, 3)).astype(np.float32)
    return org, (target - org).astype(np.float32)


@pytest.fixture(scope="module")
def scene():
    v, t = box_scene()
    return rtt.Scene.from_arrays(v, t)


def test_scene_from_arrays(scene):
    v, t = box_scene()
    assert scene.triangle_count == len(t)
    lo, hi = scene.bounds
    assert lo.shape == (3,) and hi.dtype == np.float32
    np.testing.assert_array_equal(lo, v.min(axis=0).astype(np.float32))
    # float64 vertices are stored as float32: the same scene as float32 input.
    same = rtt.Scene.from_arrays(v.astype(np.float32), t.astype(np.uint64))
    o, d = random_rays(500)
    np.testing.assert_array_equal(scene.tracer("ray").intersect(o, d)[0], same.tracer("ray").intersect(o, d)[0])


@pytest.mark.parametrize("vertices, triangles, message", [
    (np.zeros((3, 2)), np.array([[0, 1, 2]]), "shape"),
    (np.zeros((3, 3), dtype=np.int32), np.array([[0, 1, 2]]), "float32 or float64"),
    (np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]], dtype=np.float32), np.array([[0, 1, 2]]), "NaN"),
    (np.array([[0, 0, 0], [1, 0, 1e300], [0, 1, 0]]), np.array([[0, 1, 2]]), "NaN or infinite"),
    (np.eye(3), np.array([[0, 1, 3]]), "out of range"),
    (np.eye(3), np.array([[0, -1, 2]]), "out of range"),
    (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "integer"),
])
@pytest.mark.filterwarnings("ignore:overflow encountered in cast")
def test_bad_arrays_raise_value_error(vertices, triangles, message):
    with pytest.raises(ValueError, match=message):
        rtt.Scene.from_arrays(vertices, triangles)


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        rtt.load(str(tmp_path / "missing.obj"))
    bad = tmp_path / "bad.json"
    bad.write_text("{ not json")
    with pytest.raises(RuntimeError):
        rtt.load(str(bad))
    with pytest.raises(ValueError):
        rtt.load("room").tracer("no-such-kind")


def test_repairs_are_reported_and_refused_when_strict(tmp_path):
    # a NaN vertex: its triangle is dropped with a warning (docs/robustness.md, "Reading policy")
    obj = tmp_path / "nan.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\nf 1 2 4\n")
    scene = rtt.load(str(obj))
    assert scene.triangle_count == 1
    assert len(scene.warnings) == 1 and "NaN or infinite" in scene.warnings[0]
    with pytest.raises(RuntimeError, match="refused under strict=True"):
        rtt.load(str(obj), strict=True)
    assert rtt.load("room", strict=True).warnings == []


@pytest.mark.parametrize("kind", EXACT_KINDS)
def test_empty_scene_misses_everything(kind):
    # no triangles (from arrays, or a file whose every triangle was dropped): every ray misses
    empty = rtt.Scene.from_arrays(np.eye(3), np.zeros((0, 3), dtype=np.int32))
    assert empty.triangle_count == 0
    o, d = random_rays(100)
    t, tri = empty.tracer(kind).intersect(o, d)
    assert np.all(tri == -1) and np.all(np.isinf(t))
    assert np.all(empty.tracer(kind).visible(o, d))


@pytest.mark.parametrize("kind", EXACT_KINDS)
def test_every_kind_agrees_with_ray(scene, kind):
    o, d = random_rays(4001)
    rng = np.random.default_rng(5)
    tmax = np.where(rng.uniform(size=len(d)) < 0.3, rng.uniform(0.2, 1.0, len(d)), np.inf).astype(np.float32)
    t_ref, tri_ref = scene.tracer("ray").intersect(o, d, 0.0, tmax)
    t, tri = scene.tracer(kind).intersect(o, d, 0.0, tmax)
    assert t.dtype == np.float32 and tri.dtype == np.int64 and t.shape == (len(d),)
    assert 0 < (tri_ref >= 0).sum() < len(d)
    np.testing.assert_array_equal(tri, tri_ref)
    np.testing.assert_array_equal(t, t_ref)
    assert np.all(np.isinf(t[tri < 0]))
    vis = scene.tracer(kind).visible(o, d, 0.0, tmax)
    assert vis.dtype == np.bool_
    np.testing.assert_array_equal(vis, tri_ref < 0)


def test_every_isa_gives_the_same_bits(scene):
    o, d = random_rays(3001)
    widest = rtt.isa()
    assert widest in ("sse4.2", "avx2", "avx512")
    try:
        answers = []
        for isa in ("sse4.2", "avx2", "avx512"):
            rtt.limit_isa(isa)  # an ISA this CPU lacks falls back to the widest below it
            assert rtt.isa() in ("sse4.2", "avx2", "avx512")
            answers.append(scene.tracer("rtt").intersect(o, d))
        for t, tri in answers[1:]:
            np.testing.assert_array_equal(tri, answers[0][1])
            np.testing.assert_array_equal(t, answers[0][0])
        rtt.limit_isa("sse4.2")
        assert rtt.isa() == "sse4.2" and "packet16" not in rtt.tracer_kinds()
        with pytest.raises(RuntimeError, match="unknown ISA"):
            rtt.limit_isa("mmx")
    finally:
        rtt.limit_isa(widest)


@pytest.mark.skipif(not EMBREE_KINDS, reason="built without Embree")
def test_embree_modes_and_builds(scene):
    # Packets, stream and single rays, each with the HIGH and the MEDIUM build; Embree's own
    # arithmetic may break an exact tie (shared edge) differently, nothing else.
    assert set(EMBREE_KINDS) == {"embree", "embree-stream", "embree1", "embree-medium",
                                 "embree-stream-medium", "embree1-medium"}
    o, d = random_rays(4001)
    _, tri_ref = scene.tracer("ray").intersect(o, d)
    for kind in EMBREE_KINDS:
        t, tri = scene.tracer(kind).intersect(o, d)
        assert (tri != tri_ref).sum() <= 4, kind
        vis = scene.tracer(kind).visible(o, d)
        assert (vis != (tri_ref < 0)).sum() <= 4, kind


def test_any_memory_layout(scene):
    o, d = random_rays(1000)
    tracer = scene.tracer("packet")
    expected = tracer.intersect(o, d)[1]
    np.testing.assert_array_equal(tracer.intersect(np.asfortranarray(o), np.asfortranarray(d))[1], expected)
    wide = np.zeros((1000, 6), dtype=np.float64)
    wide[:, ::2] = d
    np.testing.assert_array_equal(tracer.intersect(o, wide[:, ::2])[1], expected)
    # One origin for every ray broadcasts.
    np.testing.assert_array_equal(tracer.intersect(o[0], d)[1], tracer.intersect(np.repeat(o[:1], 1000, 0), d)[1])


@pytest.mark.parametrize("origins, directions, kwargs, message", [
    (np.zeros((4, 3)), np.ones((5, 3)), {}, "differ in length"),
    (np.zeros((4, 3)), np.zeros((4, 3)), {}, "zero"),
    (np.zeros((4, 3)), np.full((4, 3), np.nan), {}, "NaN"),
    (np.zeros((4, 2)), np.ones((4, 3)), {}, "shape"),
    (np.zeros((4, 3)), np.ones((4, 3)), {"tmin": 2.0, "tmax": 1.0}, "tmin > tmax"),
    (np.zeros((4, 3)), np.ones((4, 3)), {"tmax": np.ones(3)}, "shape"),
    ("abc", np.ones((4, 3)), {}, ""),
])
def test_bad_rays_raise_value_error(scene, origins, directions, kwargs, message):
    with pytest.raises(ValueError, match=message):
        scene.tracer("ray").intersect(origins, directions, **kwargs)


def test_large_batches_name_their_first_bad_row(scene):
    # Rays are made on several threads; the message still names the first faulty row.
    o, d = random_rays(100_000)
    d[90_000] = 0.0
    d[70_001, 1] = np.inf
    o[80_000, 2] = np.nan
    tracer = scene.tracer("bvh")
    with pytest.raises(ValueError, match="origins: row 80000 has a NaN"):
        tracer.intersect(o, d, threads=2)
    o[80_000, 2] = 0.0
    with pytest.raises(ValueError, match="directions: row 70001 has a NaN"):
        tracer.visible(o, d, threads=2)
    d[70_001, 1] = 1.0
    with pytest.raises(ValueError, match="directions: row 90000 is zero"):
        tracer.intersect(o, d)
    d[90_000, 0] = 1.0
    tmax = np.full(100_000, np.inf)
    tmax[55_555] = -1.0
    with pytest.raises(ValueError, match="ray 55555: tmin > tmax"):
        tracer.visible(o, d, tmax=tmax)
    with pytest.raises(ValueError, match="threads must be at least 0"):
        tracer.intersect(o, d, threads=-1)
    # Made on one thread or two, the same rays.
    np.testing.assert_array_equal(tracer.intersect(o, d, threads=1)[1], tracer.intersect(o, d, threads=2)[1])


def sample_grid(buffer):
    """(H, W, K, K) as rtt.read_hits gives it -> the (H*K, W*K) sample grid of camera_hits."""
    h, w, k, _ = buffer.shape
    return buffer.transpose(0, 2, 1, 3).reshape(h * k, w * k)


CAMERA = [5.0, 3.0, 4.0, 0.0, 0.3, 0.0, 0.0, 1.0, 0.0, 50.0]


def write_obj(path, v, t):
    lines = ["v %r %r %r" % tuple(float(c) for c in np.float32(x)) for x in v]
    lines += ["f %d %d %d" % tuple(i + 1 for i in f) for f in t]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("aa", [1, 3])
def test_camera_hits_and_visible_match_cli_buffers(tmp_path, rtt_cli, aa):
    v, t = box_scene()
    mesh = tmp_path / "box.obj"
    write_obj(mesh, v, t)
    w, h, light = 37, 21, (0.5, 4.0, 1.0)
    subprocess.run([rtt_cli, "render", "--mesh", str(mesh), "--size", "%dx%d" % (w, h), "--aa", str(aa),
                    "--camera", ",".join(repr(c) for c in CAMERA), "--light", "0.5,4,1", "-q",
                    "--hits", str(tmp_path / "h.rtth"), "--shadows", str(tmp_path / "s.rtts")], check=True)
    cli_hits = sample_grid(rtt.read_hits(tmp_path / "h.rtth"))
    shadows, lights = rtt.read_shadows(tmp_path / "s.rtts")
    assert lights == 1 and shadows.shape == (h, w, aa, aa, 1)
    cli_shadows = sample_grid(shadows[..., 0])

    scene = rtt.load(str(mesh))
    tracer = scene.tracer("rtt")
    t_grid, tri = tracer.camera_hits(CAMERA, w, h, aa=aa)
    assert tri.shape == (h * aa, w * aa)
    np.testing.assert_array_equal(tri, cli_hits)
    stats = tracer.last_stats
    tx, ty = (w + 3) // 4, (h + 3) // 4  # padded to whole 4x4-pixel tiles, as the renderer does
    tiles = tx * ty
    r = 8 if aa == 1 else 2 if aa <= 8 else 1  # tiles per region side (the renderer's default)
    regions = -(-tx // r) * -(-ty // r)
    assert stats["tiles"] == regions and stats["rays"] == tiles * 16 * aa * aa
    assert stats["rays"] == stats["traced"] + stats["answered"]
    # every region is answered from a list or declined for one reason
    assert stats["tiles"] == stats["rtt_tiles"] + sum(stats["declined"].values())
    assert set(stats["declined"]) == {"no_shaft", "no_end", "budget", "list_full", "corners_parted"}
    assert 0 <= stats["fallback_seconds"] <= stats["seconds"]
    if aa > 1:
        assert stats["rtt_tiles"] > 0 and stats["answered"] > 0
    _, tri_again, how = tracer.camera_hits(CAMERA, w, h, aa=aa, answers=True)
    np.testing.assert_array_equal(tri_again, tri)
    assert how.dtype == np.uint8 and set(np.unique(how)) <= {0, 1, 2}
    assert (how > 0).sum() <= tracer.last_stats["answered"]  # padding samples are not in the grid

    # Shadow segments from the light to each hit point p = org + t dir, as CONVENTIONS computes them.
    org, dirs = rtt.camera_rays(CAMERA, w, h, aa=aa)
    hit = tri >= 0
    p = org + t_grid[hit][:, None] * dirs[hit]
    L = np.array(light, dtype=np.float32)
    visible = tracer.visible(L, (p - L).astype(np.float32), 1e-4, 1 - 1e-4)
    expected = np.zeros_like(cli_shadows)
    expected[hit] = visible
    np.testing.assert_array_equal(expected, cli_shadows)
    assert 0 < visible.sum() < visible.size


def decode_png_rgb(path):
    """A minimal decoder for the 8-bit RGB PNGs rtt writes (all five filter types)."""
    data = pathlib.Path(path).read_bytes()
    pos, idat, w, h = 8, b"", 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (8, 2)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, bpp = zlib.decompress(idat), w * 3, 3
    out = np.zeros((h, stride), dtype=np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        row = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        prev = out[y - 1] if y else np.zeros(stride, np.int32)
        cur = np.zeros(stride, np.int32)
        for x in range(stride):
            a = cur[x - bpp] if x >= bpp else 0
            b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
            if f == 0: pred = 0
            elif f == 1: pred = a
            elif f == 2: pred = b
            elif f == 3: pred = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (row[x] + pred) & 255
        out[y] = cur
    return out.reshape(h, w, 3).astype(np.uint8)


def test_render_matches_cli_image(tmp_path, rtt_cli):
    w, h = 40, 28
    subprocess.run([rtt_cli, "render", "--scene", "room", "--size", "%dx%d" % (w, h), "--aa", "2", "-q",
                    "-o", str(tmp_path / "room.png")], check=True)
    image = rtt.render(rtt.load("room"), width=w, height=h, aa=2, threads=1)
    assert image.shape == (h, w, 3) and image.dtype == np.uint8
    np.testing.assert_array_equal(image, decode_png_rgb(tmp_path / "room.png"))


def test_render_auto_takes_bvh_then_rtt_with_the_same_pixels():
    # A 48-triangle scene: rtt takes over once its frames were given 300 * 48 rays.
    v, t = box_scene(2)
    reference = rtt.render(rtt.Scene.from_arrays(v, t), width=64, height=48, tracer="rtt", threads=1)
    s = rtt.Scene.from_arrays(v, t)
    kinds = []
    for _ in range(12):
        kinds.append(s.auto_kind)
        np.testing.assert_array_equal(rtt.render(s, width=64, height=48, threads=1), reference)
        if kinds[-1] == "rtt":
            break
    assert kinds[0] == "bvh" and kinds[1] == "bvh" and kinds[-1] == "rtt", kinds
    # A kd-tree built for another tracer is used at once.
    built = rtt.Scene.from_arrays(v, t)
    built.tracer("packet")
    assert built.auto_kind == "rtt"
    np.testing.assert_array_equal(rtt.render(built, width=64, height=48, threads=1), reference)
    with pytest.raises(ValueError):
        rtt.render(s, width=64, height=48, tracer="no-such-kind")


def test_threads_share_a_tracer(scene):
    tracer = scene.tracer("rtt")
    batches = [random_rays(3000, seed) for seed in range(8)]
    expected = [tracer.intersect(o, d, threads=1)[1] for o, d in batches]
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        got = list(pool.map(lambda od: tracer.intersect(*od)[1], batches))
    for e, g in zip(expected, got):
        np.testing.assert_array_equal(e, g)


def test_million_rays(scene):
    o, d = random_rays(1_000_000, seed=9)
    tracer = scene.tracer("packet")
    t, tri = tracer.intersect(o, d)
    assert t.shape == (1_000_000,) and tracer.last_stats["rays"] == 1_000_000
    sample = slice(0, 1_000_000, 997)
    np.testing.assert_array_equal(tri[sample], scene.tracer("ray").intersect(o[sample], d[sample])[1])


def test_buffer_readers_refuse_malformed_files(tmp_path):
    def write(name, data):
        (tmp_path / name).write_bytes(data)
        return tmp_path / name

    header = struct.pack("<4sIIII", b"RTTH", 1, 2, 1, 4)
    good = write("good.rtth", header + struct.pack("<8I", 0, 1, 2, 3, 4, 5, 6, 0xFFFFFFFF))
    hits = rtt.read_hits(good)
    assert hits.shape == (1, 2, 2, 2) and hits[0, 1, 1, 1] == -1 and hits[0, 1, 0, 1] == 5
    for name, data, message in [
            ("short.rtth", header + struct.pack("<7I", *range(7)), "samples"),
            ("magic.rtth", b"RTTS" + header[4:] + bytes(32), "not an RTTH"),
            ("version.rtth", struct.pack("<4sIIII", b"RTTH", 2, 2, 1, 4) + bytes(32), "version"),
            ("grid.rtth", struct.pack("<4sIIII", b"RTTH", 1, 2, 1, 3) + bytes(24), "K x K"),
            ("empty.rtth", b"", "not an RTTH")]:
        with pytest.raises(ValueError, match=message):
            rtt.read_hits(write(name, data))
    shadows, lights = rtt.read_shadows(write("s.rtts", struct.pack("<4sIIIII", b"RTTS", 1, 1, 1, 1, 3) +
                                            struct.pack("<I", 0b101)))
    assert lights == 3 and shadows[0, 0, 0, 0].tolist() == [True, False, True]
