#!/usr/bin/env python3
"""Our unfolding against CGAL's Surface_mesh_parameterization (LSCM and ARAP)
on single discs (no seam tolerance, so one piece each): edge strain and time.

    /usr/bin/python3 bench/pattern_cgal.py [--build BUILD]

Needs Debian's libcgal-dev (only for this); compiles bench/pattern_cgal.cpp
into BUILD/bin/pattern_cgal once (about 2.5 min). Prints one row per mesh;
docs/pattern.md has the table of a run."""
import argparse
import pathlib
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "bench"))

from devkit import meshes, paths
from pattern import band


def write_off(path, pos, tri):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(pos), len(tri)))
        for p in pos:
            f.write("%.17g %.17g %.17g\n" % tuple(p))
        for t in tri:
            f.write("3 %d %d %d\n" % tuple(t))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=str(paths.build_dir()))
    args = ap.parse_args()
    from devkit.binding import native

    native.os.environ[native.ENV_VAR] = str(paths.library_path(args.build))
    native.load(force_reload=True)
    binary = pathlib.Path(args.build) / "bin" / "pattern_cgal"
    if not binary.exists():
        subprocess.run(
            [
                "g++",
                "-O2",
                "-DNDEBUG",
                "-std=c++17",
                "-I/usr/include/eigen3",
                "-DCGAL_EIGEN3_ENABLED",
                str(REPO / "bench" / "pattern_cgal.cpp"),
                "-o",
                str(binary),
                "-lgmp",
                "-lmpfr",
            ],
            check=True,
        )
    pos, tri = meshes.noisy_cylinder_patch(seed=22)
    result = native.run(pos, tri)
    cases = {
        "noisy patch after the engine": (result.positions, tri),
        "noisy patch as it is": meshes.noisy_cylinder_patch(seed=22),
        "sphere cap 60°": meshes.sphere_cap(60),
        "exact curved fold 100k": band(100_000),
    }
    with tempfile.TemporaryDirectory() as tmp:
        off = pathlib.Path(tmp) / "m.off"
        for name, (p, t) in cases.items():
            write_off(off, p, t)
            start = time.perf_counter()
            ours = native.unfold(p, t, params={"layout": 0, "seam_tolerance": 0})
            seconds = time.perf_counter() - start
            cgal = subprocess.run([str(binary), str(off)], capture_output=True, text=True, check=True).stdout
            print(
                "| %s | %d | ours: max %.2e mean %.2e %.3f s | %s |"
                % (
                    name,
                    len(t),
                    ours.stats["max_strain"],
                    ours.stats["mean_strain"],
                    seconds,
                    cgal.strip().replace("\n", " | "),
                )
            )


if __name__ == "__main__":
    main()
