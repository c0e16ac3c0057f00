"""Benchmark meshes: the shared real meshes and generated ones of any size.

Generated grids use the same alternating diagonals as tests/meshgen.py, but
built with numpy so that a million faces take a second, not a minute."""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests"))
import meshgen  # noqa: E402

SHARED = pathlib.Path("/work/shared/meshes")


def grid_triangles(rows, cols, wrap=False):
    """Same triangles, same order, as meshgen.grid_triangles."""
    col_count = cols if wrap else cols - 1
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(col_count), indexing="ij")
    i, j = i.ravel(), j.ravel()
    a = i * cols + j
    b = i * cols + (j + 1) % cols
    c = (i + 1) * cols + j
    d = (i + 1) * cols + (j + 1) % cols
    even = ((i + j) % 2 == 0)[:, None]
    first = np.where(even, np.stack([a, b, d], 1), np.stack([a, b, c], 1))
    second = np.where(even, np.stack([a, d, c], 1), np.stack([b, d, c], 1))
    return np.stack([first, second], 1).reshape(-1, 3).astype(np.int32)


def _band_size(faces):
    """rows, cols of a closed band with rows - 1 = cols / 2 and ~faces faces."""
    cols = max(8, int(round(np.sqrt(faces))))
    cols += cols % 2
    return cols // 2 + 1, cols


def _noise(positions, amplitude, seed):
    return meshgen.add_noise(positions, amplitude, seed)


def noisy_cylinder(faces, noise=0.03, seed=1):
    """Closed cylinder band (radius 1, height pi, square cells) with uniform
    noise of `noise` grid spacings on every coordinate."""
    rows, cols = _band_size(faces)
    t = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    z = np.linspace(0, np.pi, rows)
    tt, zz = np.meshgrid(t, z)
    pos = np.stack([np.cos(tt).ravel(), np.sin(tt).ravel(), zz.ravel()], axis=1)
    return _noise(pos, noise * 2 * np.pi / cols, seed), grid_triangles(rows, cols, wrap=True)


def noisy_cone(faces, noise=0.03, seed=2):
    """Closed cone frustum band (radius 1.5 to 0.6 over height 1.5) with noise
    of `noise` mean grid spacings."""
    rows, cols = _band_size(faces)
    t = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    s = np.linspace(0, 1, rows)
    tt, ss = np.meshgrid(t, s)
    r = 1.5 - 0.9 * ss
    pos = np.stack([(r * np.cos(tt)).ravel(), (r * np.sin(tt)).ravel(), 1.5 * ss.ravel()], 1)
    return _noise(pos, noise * 2 * np.pi * 1.05 / cols, seed), grid_triangles(rows, cols, wrap=True)


def generalized_cone(rows, cols, span=2 * np.pi, waist=0.5, pleats=8, pleat_depth=0.08,
                     height=1.6, wave=0.02, waves=2):
    """A generalized cone (apex at the origin, rulings to a pleated directrix
    r(theta) = 1 + pleat_depth sin(pleats theta), z = -height), cut between
    s = waist and s = 1 of the ruling, with wavy rulings: every ruling is
    bent sideways (radially) by wave * sin(waves pi u), u in [0, 1] along the
    band. wave = 0 is exactly developable."""
    closed = np.isclose(span, 2 * np.pi)
    t = np.linspace(0, span, cols, endpoint=not closed)
    s = np.linspace(waist, 1.0, rows)
    tt, ss = np.meshgrid(t, s)
    r = 1.0 + pleat_depth * np.sin(pleats * tt)
    u = (ss - waist) / (1.0 - waist)
    radial = ss * r + wave * np.sin(waves * np.pi * u)
    pos = np.stack([(radial * np.cos(tt)).ravel(), (radial * np.sin(tt)).ravel(),
                    (-height * ss).ravel()], 1)
    return pos, grid_triangles(rows, cols, wrap=closed)


def wavy_generalized_cone(faces):
    """The scaling family: a closed pleated generalized cone band with two
    waves along every ruling."""
    rows, cols = _band_size(faces)
    return generalized_cone(rows, cols)


def skirt():
    """Table II's skirt stand-in: an open (slit) pleated generalized cone of
    29 x 34 vertices = 986 v, 1848 f as in the paper, one bulge along the
    rulings; mean |defect| and AE are tuned near the paper's 4.91e-3 and 0.1113."""
    pos, tris = generalized_cone(rows=29, cols=34, span=2 * np.pi * 0.9, waist=0.45, pleats=6,
                                 pleat_depth=0.06, height=2.2, wave=0.1556, waves=1)
    return pos * 0.9679, tris


FAMILIES = {"cylinder": noisy_cylinder, "cone": noisy_cone, "gcone": wavy_generalized_cone}
FAMILY_TITLES = {"cylinder": "noisy cylinder", "cone": "noisy cone",
                 "gcone": "generalized cone, wavy rulings"}


def load(spec):
    """(positions, triangles) of a mesh spec dict: {'file': path} |
    {'family': name, 'faces': n} | {'named': 'curved_cone' | 'skirt'}."""
    if "file" in spec:
        return meshgen.read_obj(spec["file"])
    if "family" in spec:
        return FAMILIES[spec["family"]](int(spec["faces"]))
    if spec["named"] == "curved_cone":
        return meshgen.curved_cone()
    if spec["named"] == "skirt":
        return skirt()
    raise ValueError(spec)
