"""Instruction-count profile of the pipeline with valgrind's callgrind.

Instruction counts do not depend on the machine's load, so they are
repeatable here where wall time is not. The engine is built once more with
-g (same -O level as Release) into a scratch folder, the command-line tool
runs on a mesh under callgrind, and the inclusive counts of the pipeline's
stage functions are read back with callgrind_annotate."""
import collections
import pathlib
import re
import shutil
import subprocess
import tempfile

REPO = pathlib.Path(__file__).resolve().parent.parent

# Stage functions of native/pipeline/ (inclusive cost = the stage), in
# pipeline order. Matched against the demangled name without arguments.
STAGES = [
    ("read + write mesh file (tool)", ["developable_tool::read_raw_mesh", "developable_tool::write_mesh"]),
    ("input check", ["developable::validate_mesh"]),
    ("ideal curve fit (effect field, skeleton, B-splines)", ["developable::fit_patch_curves"]),
    ("nearest targets on the curves", ["developable::patch_target_normals"]),  # + its threads
    ("segmentation", ["developable::segment_mesh"]),
    ("MLS row weights", ["developable::mls_row_weights"]),
    ("system build + factorization (t_D)", ["developable::NormalGuidedDeformation::NormalGuidedDeformation"]),
    ("new targets into the system", ["developable::NormalGuidedDeformation::set_targets"]),
    ("linear solve per iteration", ["developable::NormalGuidedDeformation::step"]),
    ("angle defects", ["developable::angle_defects"]),
    ("face normals + areas", ["developable::face_normals", "developable::face_areas"]),
    ("tolerance clamp", ["developable::clamp_to_tolerance", "developable::(anonymous namespace)::clamp_to_tolerance"]),
    (
        "auto-segmentation check",
        ["developable::(anonymous namespace)::curve_fit_error", "developable::curve_fit_error"],
    ),
]

# Threads started inside a stage, by a function name in the thread's type.
THREAD_STAGES = [("nearest targets on the curves", "nearest_on_curves")]

LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*?):(.*?)(?:\s+\[(.*)\])?$")


def available():
    return shutil.which("valgrind") is not None and shutil.which("callgrind_annotate") is not None


# Release optimisation, plus symbols, and no inlining of functions that are not
# declared inline: every stage function of pipeline.cpp keeps its own frame at
# every call site (with plain -O3 some call sites are inlined and their cost
# lands in run_pipeline), while Eigen's inline code is still inlined. The
# total instruction count stays within a few % of the plain Release build.
PROFILE_FLAGS = "-g -fno-inline-functions -fno-inline-functions-called-once -fno-inline-small-functions"


def build(build_dir):
    """Release build for profiling (see PROFILE_FLAGS)."""
    subprocess.run(
        [
            "cmake",
            "-S",
            str(REPO),
            "-B",
            str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DCMAKE_CXX_FLAGS=" + PROFILE_FLAGS,
        ],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    subprocess.run(
        ["cmake", "--build", str(build_dir), "-j2", "--target", "developable_tool"],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    return build_dir / "bin" / "developable"


def _bare(name):
    """Function name without its argument list and return type."""
    depth, cut = 0, len(name)
    for i, ch in enumerate(name):
        if ch == "(" and depth == 0 and not name[:i].endswith("anonymous namespace"):
            if not name[i:].startswith("(anonymous"):
                cut = i
                break
        depth += ch == "<"
        depth -= ch == ">"
    return name[:cut].strip()


def annotate(out_file, inclusive):
    text = subprocess.run(
        [
            "callgrind_annotate",
            "--threshold=100",
            "--auto=no",
            "--inclusive=" + ("yes" if inclusive else "no"),
            str(out_file),
        ],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    total, costs = None, collections.Counter()
    for line in text.splitlines():
        if "PROGRAM TOTALS" in line:
            total = int(line.split()[0].replace(",", ""))
            continue
        m = LINE.match(line)
        if m:
            # Inlined code is listed again under the header it came from. Exclusive
            # counts of those entries are disjoint (sum them); inclusive ones
            # overlap, and the entry of the function's own file holds the whole
            # call tree (take the largest).
            name, cost = _bare(m.group(3)), int(m.group(1).replace(",", ""))
            costs[name] = max(costs[name], cost) if inclusive else costs[name] + cost
    return total, costs


def profile(tool, mesh_obj, extra_args=()):
    """{'total': Ir, 'pipeline': Ir of run_pipeline and its threads, 'stages': [(name, Ir)],
    'self': [(function, Ir)] top exclusive}."""
    with tempfile.TemporaryDirectory(prefix="bench-callgrind-") as tmp:
        out_file = pathlib.Path(tmp) / "callgrind.out"
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                "--callgrind-out-file=" + str(out_file),
                str(tool),
                str(mesh_obj),
                str(pathlib.Path(tmp) / "out.obj"),
                "--quiet",
                *extra_args,
            ],
            check=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        return summarize(out_file)


def summarize(out_file):
    """Stage and hottest-function table of one callgrind output file."""
    total, incl = annotate(out_file, True)
    _, excl = annotate(out_file, False)
    # Worker threads (std::thread) are call-tree roots of their own in callgrind:
    # their cost is not under run_pipeline. Add each to the stage that starts it.
    threads = {n: c for n, c in incl.items() if n.startswith("std::thread::_State_impl")}
    extra = collections.Counter()
    for name, cost in threads.items():
        title = next((t for t, marker in THREAD_STAGES if marker in name), "other worker threads")
        extra[title] += cost
    stages = []
    for title, names in STAGES:
        cost = sum(incl.get(n, 0) for n in names) + extra.pop(title, 0)
        if cost:
            stages.append((title, cost))
    stages += list(extra.items())
    pipeline = incl.get("developable::run_pipeline", 0) + sum(threads.values())
    return {"total": total, "pipeline": pipeline, "stages": stages, "self": excl.most_common(12)}
