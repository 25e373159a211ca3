"""Readers of the command line's hit and shadow buffers (CONVENTIONS: little-endian u32 fields;
samples ordered by pixel row y, pixel x, sample row j, sample i), as numpy arrays shaped
(height, width, K, K) so that buffer[y, x, j, i] is sample (i, j) of pixel (x, y)."""
import os

import numpy as np


def _read(path, magic, header_words):
    with open(os.fspath(path), "rb") as f:
        data = f.read()
    if len(data) < 4 + 4 * header_words or data[:4] != magic:
        raise ValueError(f"{path}: not an {magic.decode()} buffer")
    header = np.frombuffer(data, dtype="<u4", count=header_words, offset=4)
    if header[0] != 1:
        raise ValueError(f"{path}: {magic.decode()} version {header[0]}, expected 1")
    width, height, spp = (int(v) for v in header[1:4])
    k = int(round(spp ** 0.5))
    if k * k != spp or width < 1 or height < 1:
        raise ValueError(f"{path}: {width}x{height} with {spp} samples per pixel is not a K x K grid")
    payload = np.frombuffer(data, dtype="<u4", offset=4 + 4 * header_words)
    if payload.size != width * height * spp:
        raise ValueError(f"{path}: {payload.size} samples, the header says {width * height * spp}")
    return header, payload.reshape(height, width, k, k)


def read_hits(path):
    """The closest triangle of every sample of an RTTH file: int64, -1 on a miss (as
    Tracer.intersect), shaped (height, width, K, K)."""
    _, hits = _read(path, b"RTTH", 4)
    out = hits.astype(np.int64)
    out[hits == 0xFFFFFFFF] = -1
    return out


def read_shadows(path):
    """An RTTS file as (visible, lights): visible[y, x, j, i, l] is True when light l is visible
    from the hit of that sample (False for a miss), and lights the file's light count."""
    header, bits = _read(path, b"RTTS", 5)
    lights = int(header[4])
    if lights > 32:
        raise ValueError(f"{path}: {lights} lights; at most 32")
    visible = (bits[..., None] >> np.arange(lights, dtype=np.uint32)) & 1
    return visible.astype(bool), lights
