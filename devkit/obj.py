"""Wavefront OBJ: vertices and faces only, as the engine's tool reads them."""
import numpy as np


def write_obj(path, positions, triangles):
    """Writes every vertex and triangle as given (17 significant digits, so
    that the file reads back bit for bit; inf, nan, loose vertices and
    out-of-range indices are written as they are, for bad-input tests)."""
    with open(path, "w") as f:
        np.savetxt(f, np.asarray(positions, dtype=np.float64).reshape(-1, 3), fmt="v %.17g %.17g %.17g")
        np.savetxt(f, np.asarray(triangles, dtype=np.int64).reshape(-1, 3) + 1, fmt="f %d %d %d")


def read_obj(path):
    """(positions float64 (n, 3), triangles int32 (m, 3)); polygons are split
    into fans, texture and normal indices are ignored."""
    pos, tris = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                pos.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
                for k in range(1, len(idx) - 1):
                    tris.append([idx[0], idx[k], idx[k + 1]])
    return (np.array(pos, dtype=np.float64).reshape(-1, 3), np.array(tris, dtype=np.int32).reshape(-1, 3))
