"""Writes benchmarks.md and the bench-*.png plots from the rows of bench/run.py."""
import math
import pathlib

import numpy as np

from devkit.meshes import FAMILY_TITLES

# The paper's Tables I and II (its machine: Intel Core 2, 2.13 GHz, 2 GB; times in ms).
PAPER = {
    "curved_cone": {
        "title": "Table I: curved cone (paper: 720 v, 1280 f, E_before 2.498e-3, AE 0.1169)",
        "rows": {
            (0.02, 15.0): (2.48e-3, -0.57, 5.58, 102.3, 107.88),
            (10.0, 5.0): (8.03e-4, -67.8, 5.57, 44.18, 49.75),
        },
    },
    "skirt": {
        "title": "Table II: skirt (paper: 986 v, 1848 f, E_before 4.91e-3, AE 0.1113, omega 5)",
        "rows": {(0.33, 5.0): (4.86e-3, -0.99, 9.88, 14.18, 24.06), (10.0, 5.0): (8.03e-4, -67.8, 10.23, 1.39, 11.62)},
    },
}
VARIANTS = ["refit, seg auto", "paper, seg auto", "refit, seg on", "refit, seg off"]


def fmt(x, digits=3):
    if x is None:
        return "–"
    if isinstance(x, str):
        return x
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if x == 0:
        return "0"
    if abs(x) >= 10 ** digits or abs(x) < 1e-3:
        return "%.*e" % (digits - 1, x)
    return "%.*g" % (digits, x)


def ms(x):
    if x is None:
        return "–"
    return "%.1f" % x if x < 1e4 else "%.0f" % x


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        lines.append("| " + " | ".join(r) + " |")
    return "\n".join(lines)


def ok(row):
    return row is not None and "error" not in row


def quality_cells(r):
    move = r.get("max_move")
    return [
        fmt(r["mean_after"]),
        fmt(r["max_after"]),
        "%.1f" % r["dE"],
        "%.2f → %.2f" % (r["flat_before"], r["flat_after"]),
        fmt(r.get("hausdorff")),
        fmt(move / r["AE"] if move is not None and r["AE"] else None),
    ]


MESH_HEADER = [
    "mesh",
    "#v",
    "#f",
    "AE",
    "mean δ before",
    "max δ before",
    "mean δ after",
    "max δ after",
    "dE %",
    "flat",
    "H/diag",
    "move/AE",
    "it",
    "stop",
    "patches",
    "t_D ms",
    "t_I ms",
    "t_T ms",
    "CPU ms",
    "peak MiB",
    "run +MiB",
]


def mesh_rows(rows, label=lambda r: r["label"]):
    out = []
    for r in rows:
        if not ok(r):
            out.append(
                [label(r), "error: " + r.get("error", "?").replace("|", "/")[:120]] + [""] * (len(MESH_HEADER) - 2)
            )
            continue
        out.append(
            [label(r), str(r["v"]), str(r["f"]), fmt(r["AE"]), fmt(r["mean_before"]), fmt(r["max_before"])]
            + quality_cells(r)
            + [
                str(r.get("iterations", "–")),
                str(r.get("stop_reason", "–")),
                str(r.get("patches", "–")),
                ms(r.get("t_D")),
                ms(r.get("t_I")),
                ms(r.get("t_T")),
                ms(r.get("cpu_ms")),
                "%.0f" % r["peak_mib"],
                "%.0f" % (r["peak_mib"] - r.get("rss_before_mib", 0.0)),
            ]
        )
    return out


def exponent(points):
    """Least-squares slope of log y against log x, and the two-point slope
    between the first and last point."""
    pts = [(x, y) for x, y in points if x and y and y > 0]
    if len(pts) < 2:
        return None, None
    lx, ly = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    fit = float(np.polyfit(lx, ly, 1)[0])
    two = float((ly[-1] - ly[0]) / (lx[-1] - lx[0]))
    return fit, two


def scaling_series(rows):
    series = {}
    for r in rows:
        if r["section"] == "scaling" and ok(r):
            series.setdefault(r["family"], []).append(r)
    for fam in series:
        series[fam].sort(key=lambda r: r["f"])
    return series


def find(rows, section, **match):
    for r in rows:
        if r["section"] == section and all(r.get(k) == v for k, v in match.items()):
            return r
    return None


def check(flag):
    return "[x]" if flag else "[ ]"


def checklist(rows, series):
    lines = []
    cc = find(rows, "real", label="curved cone")
    paper_cc = find(rows, "paper_tables", table="curved_cone", mode="paper", e_allow=10.0, omega=5.0)
    # The curved cone: boundary pinned, E_allow 10 AE, omega 5, default (refit) mode.
    pinned_cc = find(rows, "paper_tables", table="curved_cone", mode="refit", e_allow=10.0, omega=5.0)
    if ok(cc):
        extra = ""
        if ok(paper_cc):
            extra = "; paper mode at the same settings: t_T %.1f ms" % paper_cc["t_T"]
        worst = max(cc["t_T"], pinned_cc["t_T"] if ok(pinned_cc) else 0.0)
        pinned_text = ""
        if ok(pinned_cc):
            pinned_text = (
                "t_T = %.1f ms as the issue sets it up (boundary pinned, E_allow 10 AE, "
                "omega 5, refit mode; median of %d runs, all runs %s ms, dE %.2f %%); "
                % (
                    pinned_cc["t_T"],
                    pinned_cc.get("repeats", 1),
                    ", ".join("%.1f" % x for x in pinned_cc.get("t_T_all", [pinned_cc["t_T"]])),
                    pinned_cc["dE"],
                )
            )
        lines.append(
            "- %s **Curved cone, whole pipeline < 50 ms**: %s%.1f ms with the "
            "defaults and no pins (median of %d runs; all runs %s ms)%s."
            % (
                check(worst < 50),
                pinned_text,
                cc["t_T"],
                cc.get("repeats", 1),
                ", ".join("%.1f" % x for x in cc.get("t_T_all", [cc["t_T"]])),
                extra,
            )
        )
    else:
        lines.append("- [ ] **Curved cone < 50 ms**: not measured")

    def at(faces):
        return {fam: next((r for r in rs if r.get("target_faces") == faces), None) for fam, rs in series.items()}

    hundred = {k: v for k, v in at(100_000).items() if v}
    if hundred:
        worst = max(r["t_T"] for r in hundred.values())
        lines.append(
            "- %s **100k faces < 3 s**: %s."
            % (
                check(worst < 3000),
                ", ".join("%s %.2f s" % (FAMILY_TITLES[f], r["t_T"] / 1000) for f, r in hundred.items()),
            )
        )
    else:
        lines.append("- [ ] **100k faces < 3 s**: not measured in this run")
    million = {k: v for k, v in at(1_000_000).items() if v}
    if million:
        worst_t = max(r["t_T"] for r in million.values())
        worst_m = max(r["peak_mib"] for r in million.values())
        lines.append(
            "- %s **1M faces < 30 s within 4 GiB**: %s."
            % (
                check(worst_t < 30_000 and worst_m < 4096),
                ", ".join(
                    "%s %.1f s, %.2f GiB peak" % (FAMILY_TITLES[f], r["t_T"] / 1000, r["peak_mib"] / 1024)
                    for f, r in million.items()
                ),
            )
        )
    else:
        lines.append("- [ ] **1M faces < 30 s within 4 GiB**: not measured in this run")
    exps = {}
    for fam, rs in series.items():
        pts = [(r["f"], r["t_T"]) for r in rs if r.get("target_faces", 0) >= 10_000]
        if len(pts) >= 2 and pts[-1][0] >= 900_000:
            exps[fam] = exponent(pts)
    if exps:
        worst = max(two for _, two in exps.values())
        lines.append(
            "- %s **Cost grows no faster than ~n^1.2 from 10k to 1M faces**: t_T "
            "exponent from 10k to 1M: %s."
            % (check(worst <= 1.2), ", ".join("%s %.3f" % (FAMILY_TITLES[f], two) for f, (fit, two) in exps.items()))
        )
    else:
        lines.append("- [ ] **Cost growth 10k→1M ≤ ~n^1.2**: not measured in this run")
    quality = [r for r in rows if r["section"] in ("real", "scaling")]
    bad = [
        r["label"]
        for r in quality
        if not ok(r)
        or not all(
            r.get(k) is not None and math.isfinite(r[k])
            for k in ("mean_after", "max_after", "flat_after", "hausdorff", "max_move")
        )
    ]
    lines.append(
        "- %s **Quality columns for every mesh**: %d meshes measured%s."
        % (
            check(quality and not bad),
            len(quality),
            "; missing or failed: " + ", ".join(bad) if bad else ", all columns finite",
        )
    )
    return "\n".join(lines)


def summary(rows, series):
    """A few sentences computed from the rows, so that they stay true."""
    lines = []
    measured = [r for r in rows if r["section"] in ("real", "scaling") and ok(r)]
    if measured:
        improved = [r for r in measured if r["dE"] < -1.0]
        unchanged = [r for r in measured if r.get("max_move") == 0.0]
        lines.append(
            "- Developability with the defaults: %d of %d meshes improved by more than 1 %% "
            "(dE from %.1f %% to %.1f %%); %d came back unchanged (no vertex moved, the engine "
            "found no iterate better than the input): %s."
            % (
                len(improved),
                len(measured),
                max((r["dE"] for r in improved), default=float("nan")),
                min((r["dE"] for r in improved), default=float("nan")),
                len(unchanged),
                ", ".join("%s (%d f)" % (r["label"], r["f"]) for r in unchanged) or "none",
            )
        )
    big = [r for rs in series.values() for r in rs if r["f"] >= 900_000]
    if big:
        lines.append(
            "- At 1M faces one iteration costs %s s and the runs took %s iterations; "
            "factorization (t_D) is %s of t_T."
            % (
                " / ".join("%.2f" % (r["t_I"] / 1000 / max(r["iterations"], 1)) for r in big),
                " / ".join(str(r["iterations"]) for r in big),
                " / ".join("%.0f %%" % (100 * r["t_D"] / r["t_T"]) for r in big),
            )
        )
    modes = [r for r in rows if r["section"] == "modes" and ok(r)]
    pairs = []
    for r in modes:
        if r["variant"] == "paper, seg auto":
            base = next((x for x in modes if x["label"] == r["label"] and x["variant"] == "refit, seg auto"), None)
            if base and base["mean_before"] > 0:
                pairs.append((r, base))
    if pairs:
        refit_lower = sum(1 for p, b in pairs if b["mean_after"] < p["mean_after"] * 0.99)
        paper_lower = sum(1 for p, b in pairs if p["mean_after"] < b["mean_after"] * 0.99)
        faster = sum(1 for p, b in pairs if p["t_T"] < b["t_T"])
        lines.append(
            "- Paper mode against refit mode (defaults otherwise, %d meshes): refit reaches a "
            "lower mean |δ| (by more than 1 %%) on %d, paper mode on %d, a tie on %d; paper "
            "mode is faster on %d."
            % (len(pairs), refit_lower, paper_lower, len(pairs) - refit_lower - paper_lower, faster)
        )
    return "\n".join(lines)


def paper_section(rows):
    parts = []
    for name, paper in PAPER.items():
        mine = [r for r in rows if r["section"] == "paper_tables" and r.get("table") == name]
        if not mine:
            continue
        first = next((r for r in mine if ok(r)), None)
        head = paper["title"]
        if first:
            head += "; ours: %d v, %d f, E_before %s, AE %s" % (
                first["v"],
                first["f"],
                fmt(first["mean_before"], 4),
                fmt(first["AE"], 4),
            )
        body = []
        combos = sorted({(r["e_allow"], r["omega"]) for r in mine})
        for e_allow, omega in combos:
            ref = paper["rows"].get((e_allow, omega))
            if ref:
                body.append(
                    [
                        "%g AE" % e_allow,
                        "%g" % omega,
                        "**paper**",
                        fmt(ref[0]),
                        "%.2f" % ref[1],
                        "",
                        "",
                        "",
                        "",
                        ms(ref[2]),
                        ms(ref[3]),
                        ms(ref[4]),
                    ]
                )
            for mode in ("paper", "refit"):
                r = next(
                    (x for x in mine if x["e_allow"] == e_allow and x["omega"] == omega and x["mode"] == mode), None
                )
                if r is None:
                    continue
                if not ok(r):
                    body.append(
                        ["%g AE" % e_allow, "%g" % omega, "ours, " + mode, "error: " + r["error"][:80]] + [""] * 8
                    )
                    continue
                move = r["max_move"] / r["AE"] if r.get("max_move") is not None else None
                body.append(
                    [
                        "%g AE" % e_allow,
                        "%g" % omega,
                        "ours, %s mode" % mode,
                        fmt(r["mean_after"]),
                        "%.2f" % r["dE"],
                        "%.2f → %.2f" % (r["flat_before"], r["flat_after"]),
                        fmt(r.get("hausdorff")),
                        fmt(move),
                        "%d (%s)" % (r["iterations"], r["stop_reason"]),
                        ms(r["t_D"]),
                        ms(r["t_I"]),
                        ms(r["t_T"]),
                    ]
                )
        parts.append(
            "**%s**\n\n" % head
            + table(
                [
                    "E_allow",
                    "ω",
                    "source",
                    "E_after mean",
                    "dE %",
                    "flat",
                    "H/diag",
                    "move/AE",
                    "iterations",
                    "t_D ms",
                    "t_I ms",
                    "t_T ms",
                ],
                body,
            )
        )
    return "\n\n".join(parts)


def modes_section(rows):
    mine = [r for r in rows if r["section"] == "modes"]
    labels = []
    for r in mine:
        if r["label"] not in labels:
            labels.append(r["label"])
    body = []
    for label in labels:
        for variant in VARIANTS:
            r = next((x for x in mine if x["label"] == label and x["variant"] == variant), None)
            if r is None:
                continue
            if not ok(r):
                body.append([label, variant, "error: " + r["error"][:80]] + [""] * 8)
                continue
            body.append(
                [
                    label,
                    variant,
                    str(r["f"]),
                    fmt(r["mean_before"]),
                    fmt(r["mean_after"]),
                    "%.1f" % r["dE"],
                    "%.2f" % r["flat_after"],
                    fmt(r.get("hausdorff")),
                    "%d (%s)" % (r["iterations"], r["stop_reason"]),
                    str(r["patches"]),
                    ms(r["t_T"]),
                ]
            )
    return table(
        [
            "mesh",
            "variant",
            "#f",
            "mean δ before",
            "mean δ after",
            "dE %",
            "flat after",
            "H/diag",
            "iterations",
            "patches",
            "t_T ms",
        ],
        body,
    )


def compare_section(rows, command):
    mine = [r for r in rows if r["section"] == "compare"]
    if not mine:
        return None
    header = [
        "mesh",
        "#v",
        "#f",
        "out #v/#f",
        "mean δ before",
        "mean δ after",
        "max δ after",
        "dE %",
        "flat",
        "H/diag",
        "move/AE",
        "wall ms",
        "peak MiB",
    ]
    body = []
    for r in mine:
        if not ok(r):
            body.append([r["label"], "error: " + r["error"].replace("|", "/")[:100]] + [""] * (len(header) - 2))
            continue
        q = quality_cells(r)
        body.append(
            [
                r["label"],
                str(r["v"]),
                str(r["f"]),
                "%d/%d" % (r["out_v"], r["out_f"]),
                fmt(r["mean_before"]),
                q[0],
                q[1],
                q[2],
                q[3],
                q[4],
                q[5],
                ms(r["t_T"]),
                "%.0f" % r["peak_mib"],
            ]
        )
    return (
        "Command: `%s` (wall time of the whole command including its file input and "
        "output; peak = the child's ru_maxrss).\n\n" % command + table(header, body)
    )


def profile_section(profiles):
    if profiles is None:
        return "Not run (`--no-profile` or `--quick`)."
    if "skipped" in profiles:
        return "Skipped: %s." % profiles["skipped"]
    parts = []
    for case in profiles["cases"]:
        if "error" in case:
            parts.append("**%s**: error %s" % (case["title"], case["error"]))
            continue
        pipe = case["pipeline"] or case["total"]
        stages = sorted(case["stages"], key=lambda s: -s[1])
        body = [
            [name, "%.1f" % (cost / 1e6), "%.1f %%" % (100.0 * cost / pipe)]
            for name, cost in stages
            if "tool" not in name
        ]
        inside = sum(cost for name, cost in stages if "tool" not in name)
        body.append(
            [
                "rest of run_pipeline (inlined helpers, copies)",
                "%.1f" % ((pipe - inside) / 1e6),
                "%.1f %%" % (100.0 * (pipe - inside) / pipe),
            ]
        )
        top = [
            [("`%s`" % name[:90]) if name else "?", "%.1f" % (cost / 1e6), "%.1f %%" % (100.0 * cost / case["total"])]
            for name, cost in case["self"][:10]
        ]
        parts.append(
            "**%s** — %.0f M instructions in the whole tool run, %.0f M (%.0f %%) in "
            "`run_pipeline`; callgrind took %.0f s.\n\n"
            % (case["title"], case["total"] / 1e6, pipe / 1e6, 100.0 * pipe / case["total"], case["seconds"])
            + "Stages (inclusive, share of `run_pipeline`; a stage called in every iteration is "
            "summed over all iterations):\n\n"
            + table(["stage", "M instr.", "share"], body)
            + "\n\nHottest functions (exclusive, share of the whole run):\n\n"
            + table(["function", "M instr.", "share"], top)
        )
    return "\n\n".join(parts)


def wall_stages(rows):
    """Wall-clock split of t_T by the engine's progress stages, for a few rows."""
    picks = [
        r
        for r in rows
        if ok(r)
        and r.get("stages_ms")
        and (
            (r["section"] == "real" and r["label"] in ("curved cone", "skirt", "boat", "mountain"))
            or (r["section"] == "scaling" and r.get("target_faces") in (100_000, 1_000_000))
        )
    ]
    names = []
    for r in picks:
        for n in r["stages_ms"]:
            if n not in names and n != "done":
                names.append(n)
    body = []
    for r in picks:
        total = sum(r["stages_ms"].values())
        body.append(
            [r["label"], ms(r["wall_ms"])]
            + ["%.0f %%" % (100.0 * r["stages_ms"].get(n, 0.0) / total) if total else "–" for n in names]
        )
    return table(["mesh", "wall ms"] + names, body)


# ---------------------------------------------------------------- plots


def plots(data, out):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return ["(matplotlib is not installed: no plots; `apt-get install python3-matplotlib`)"]
    written = []
    rows = data["rows"]
    series = scaling_series(rows)
    if series:
        fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(11, 4.3))
        for fam, rs in series.items():
            f = [r["f"] for r in rs]
            t = [r["t_T"] / 1000.0 for r in rs]
            m = [r["peak_mib"] for r in rs]
            m_run = [max(r["peak_mib"] - r.get("rss_before_mib", 0.0), 1e-3) for r in rs]
            big = [(r["f"], r["t_T"]) for r in rs if r["f"] >= 9_000]
            fit, two = exponent(big)
            label = FAMILY_TITLES[fam] + (" (n^%.2f from 10k)" % two if two else "")
            ax_t.loglog(f, t, "o-", label=label)
            mfit, mtwo = exponent([(r["f"], y) for r, y in zip(rs, m_run) if r["f"] >= 9_000])
            line = ax_m.loglog(f, m, "o-", label=FAMILY_TITLES[fam] + ", process peak")[0]
            ax_m.loglog(
                f,
                m_run,
                "s--",
                color=line.get_color(),
                markersize=4,
                label=FAMILY_TITLES[fam] + ", run's own" + (" (n^%.2f from 10k)" % mtwo if mtwo else ""),
            )
        anchor = next((r for rs in series.values() for r in rs if r["f"] >= 9_000), None)
        if anchor:
            xs = np.array([anchor["f"], 1.0e6])
            for p, style in ((1.0, ":"), (1.2, "--")):
                ax_t.loglog(
                    xs, anchor["t_T"] / 1000.0 * (xs / xs[0]) ** p, "k" + style, linewidth=0.8, label="n^%g guide" % p
                )
        ax_t.plot([1e5, 1e6], [3, 30], "rx", markersize=9, label="targets (3 s, 30 s)")
        ax_m.axhline(4096, color="r", linestyle="--", linewidth=0.8, label="4 GiB")
        ax_t.set_xlabel("faces")
        ax_t.set_ylabel("t_T (s)")
        ax_t.set_title("Whole pipeline time")
        ax_m.set_xlabel("faces")
        ax_m.set_ylabel("MiB")
        ax_m.set_title("Peak memory: process (incl. Python) and the run's own")
        for ax in (ax_t, ax_m):
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "bench-scaling.png", dpi=110)
        plt.close(fig)
        written.append("bench-scaling.png")
    modes = [r for r in rows if r["section"] == "modes" and ok(r)]
    if modes:
        labels = []
        for r in modes:
            if r["label"] not in labels:
                labels.append(r["label"])
        fig, (ax_e, ax_t) = plt.subplots(2, 1, figsize=(max(8, 0.75 * len(labels) + 2), 6.5), sharex=True)
        width = 0.8 / len(VARIANTS)
        for k, variant in enumerate(VARIANTS):
            ratio, times = [], []
            for label in labels:
                r = next((x for x in modes if x["label"] == label and x["variant"] == variant), None)
                ratio.append(r["mean_after"] / r["mean_before"] if r and r["mean_before"] else np.nan)
                times.append(r["t_T"] / 1000.0 if r else np.nan)
            x = np.arange(len(labels)) + (k - (len(VARIANTS) - 1) / 2) * width
            ax_e.bar(x, ratio, width, label=variant)
            ax_t.bar(x, times, width, label=variant)
        ax_e.set_yscale("log")
        ax_e.set_ylabel("mean |δ| after / before")
        ax_e.axhline(1.0, color="k", linewidth=0.6)
        ax_e.set_ylim(top=5.0)
        fig.suptitle("Paper vs refit mode, segmentation on / off / automatic (defaults otherwise)", fontsize=10)
        ax_t.set_yscale("log")
        ax_t.set_ylabel("t_T (s)")
        ax_t.set_xticks(np.arange(len(labels)))
        ax_t.set_xticklabels(labels, rotation=35, ha="right", fontsize=8)
        ax_e.legend(fontsize=7, ncol=4, loc="lower left", bbox_to_anchor=(0.0, 1.0))
        for ax in (ax_e, ax_t):
            ax.grid(True, axis="y", which="both", alpha=0.3)
        fig.tight_layout()
        fig.savefig(out / "bench-modes.png", dpi=110)
        plt.close(fig)
        written.append("bench-modes.png")
    return written


# ---------------------------------------------------------------- document


def write(data, out):
    out = pathlib.Path(out)
    rows = data["rows"]
    info = data["machine"]
    series = scaling_series(rows)
    images = plots(data, out)
    md = ["# Benchmarks", ""]
    md.append(
        "Generated by `%s` (bench/run.py) — do not edit by hand; rerun it after engine "
        "changes. %s"
        % (data["command"], "**Quick slice only (CI smoke run): not the full benchmark.**" if data.get("quick") else "")
    )
    md.append("")
    md.append(
        "Machine: %s, %s cores, %s GiB, %s, Python %s; run on %s, took %s min; load "
        "average (1, 5, 15 min) %s at the start, %s at the end. Engine "
        "`dev_version_string()` = %s (ABI %s), commit %s, %s build. The machine is shared "
        "and noisy: wall times of small runs vary by tens of percent between runs (small "
        "cases are run several times, the median is shown), the instruction counts of the "
        "profile do not."
        % (
            info["cpu"],
            info["cores"],
            info["memory_gib"],
            info["os"],
            info["python"],
            info["date"],
            info.get("bench_minutes", "?"),
            info.get("load_start"),
            info.get("load_end"),
            info.get("engine_version"),
            info.get("abi_version"),
            info.get("commit"),
            info.get("build_type"),
        )
    )
    md += ["", "## Targets", "", checklist(rows, series), ""]
    text = summary(rows, series)
    if text:
        md += ["## Summary", "", text, ""]
    md += [
        "## Columns",
        "",
        "- **#v, #f**: vertices, faces. **AE**: average edge length.",
        "- **δ**: angle defect (2π minus the angle sum, rad) at interior vertices; mean and max "
        "of |δ| before and after, computed by the benchmark in numpy (the same code for "
        "other tools' outputs). **dE %**: 100 (E_after − E_before) / E_before of the mean.",
        "- **flat**: fraction of interior vertices with |δ| < 1e-3 rad, before → after.",
        "- **H/diag**: two-sided Hausdorff distance between input and output over the input's "
        "bounding-box diagonal, sampled: exact point-to-triangle distances from the "
        "vertices, edge midpoints and centroids of each mesh to the other surface "
        "(devkit/distance.py, uniform grid).",
        "- **move/AE**: largest vertex move over AE. **it / stop**: iterations and why they "
        "stopped. **patches**: segmentation patches.",
        "- **t_D, t_I, t_T**: the engine's own timers (dev_stats): system build + "
        "factorization, iterations, whole `dev_run` call (checks, fitting, segmentation "
        "included), ms. **CPU ms**: user + system CPU time of the process during "
        "`dev_run` (all threads): less sensitive to other jobs on the machine than wall time.",
        "- **peak MiB**: peak resident memory (VmHWM, reset just before `dev_run`) of the "
        "subprocess running the case: the Python interpreter with numpy (~50 MiB) and the "
        "input arrays are included. **run +MiB**: that peak minus the resident size just "
        "before `dev_run` (what the run itself added).",
        "",
    ]
    md += [
        "## Real meshes",
        "",
        "The paper's two models, generated (devkit/meshes.py `curved_cone()` and "
        "`skirt()`), and the meshes of ../shared/meshes (sources and "
        "licences in its README; CC BY meshes: odedstein/meshes), all with the defaults "
        "(refit mode, automatic segmentation, E_allow 10 AE, omega 5, no pins).",
        "",
        table(MESH_HEADER, mesh_rows([r for r in rows if r["section"] == "real"])),
        "",
    ]
    md += [
        "## Generated meshes of growing size",
        "",
        "Closed bands with rows − 1 = cols / 2, about 1k, 10k, 100k and 1M faces, defaults. "
        "*noisy cylinder*: radius 1, height π, uniform noise of 0.03 grid spacings on every "
        "coordinate; *noisy cone*: frustum radius 1.5 → 0.6, the same noise; *generalized "
        "cone, wavy rulings*: pleated directrix r(θ) = 1 + 0.08 sin 8θ, rulings bent by "
        "0.02 sin 2πu (devkit/meshes.py). Big cases run once.",
        "",
        table(
            MESH_HEADER, mesh_rows([r for r in rows if r["section"] == "scaling"], lambda r: FAMILY_TITLES[r["family"]])
        ),
        "",
    ]
    if "bench-scaling.png" in images:
        md += ["![time and memory against size](bench-scaling.png)", ""]
    exps = []
    for fam, rs in series.items():
        big = [r for r in rs if r["f"] >= 9_000]
        if len(big) < 2:
            continue

        def k(key):
            cells = []
            for a, b in list(zip(big, big[1:])) + ([(big[0], big[-1])] if len(big) > 2 else []):
                ya, yb = key(a), key(b)
                cells.append("%.2f" % (math.log(yb / ya) / math.log(b["f"] / a["f"])) if ya > 0 and yb > 0 else "–")
            return " / ".join(cells)

        exps.append(
            [
                FAMILY_TITLES[fam],
                " / ".join("%dk" % round(r["f"] / 1000) for r in big),
                k(lambda r: r["t_T"]),
                k(lambda r: r["t_I"] / max(r["iterations"], 1)),
                " → ".join(str(r["iterations"]) for r in big),
                k(lambda r: r["peak_mib"] - r.get("rss_before_mib", 0.0)),
            ]
        )
    if exps:
        md += [
            "Growth exponents k (cost ∝ n^k, n = faces) between consecutive sizes, then over "
            "the whole range. The per-iteration cost grows about linearly; the iteration "
            "count grows too. Memory is the growth of the run itself (peak − resident size "
            "before `dev_run`).",
            "",
            table(["mesh", "faces", "k of t_T", "k of t_I per iteration", "iterations", "k of memory"], exps),
            "",
        ]
    md += [
        "## The paper's Tables I and II",
        "",
        "Boundary pinned, E_allow in {0.02, 0.33, 10} AE × omega in {5, 15}, in the paper's "
        "mode (`mode='paper'`: one set of targets, the 11-row system factored once) and in our "
        "default refit mode. The curved cone is devkit/meshes.py `curved_cone()`; the skirt "
        "is a stand-in built to the paper's counts (an open, slit, pleated generalized cone "
        "with one bulge along its rulings, devkit/meshes.py `skirt()`): the paper's meshes are "
        "not published, so only the trends compare, not the digits. The paper's times are in "
        "ms on a 2.13 GHz Core 2. Its Table II's second row repeats Table I's numbers "
        "(8.03e-4, −67.8 %), probably a copy slip in the paper.",
        "",
        paper_section(rows),
        "",
    ]
    md += [
        "## Paper mode against refit mode, segmentation on and off",
        "",
        "Defaults except the variant (no pins). *seg auto* = `segmentation=-1` (the default), " "*on* = 1, *off* = 0.",
        "",
        modes_section(rows),
        "",
    ]
    if "bench-modes.png" in images:
        md += ["![modes](bench-modes.png)", ""]
    cmp = compare_section(rows, data["command"].split("--compare", 1)[-1].strip(" '\""))
    if cmp:
        md += ["## Other tool (--compare)", "", cmp, ""]
    md += [
        "## Profile",
        "",
        "Instruction counts from `valgrind --tool=callgrind` on the command-line tool "
        "(build/bin/developable built into a scratch folder with the Release flags plus "
        "`-g -fno-inline-functions -fno-inline-functions-called-once "
        "-fno-inline-small-functions`, so that each stage function keeps its own frame; "
        "Eigen's inline code is still inlined and the total count stays within a few % of "
        "the plain Release build); "
        "repeatable on this noisy machine. Inclusive counts of the stage functions of "
        "native/pipeline/:",
        "",
        profile_section(data.get("profiles")),
        "",
        "Wall-clock split of the same runs as above, from the engine's progress callback "
        "(stage names as the engine reports them; *deformation* covers the iterations, "
        "including refits):",
        "",
        wall_stages(rows),
        "",
    ]
    md += [
        "## Reproducing",
        "",
        "```sh",
        "cmake -S . -B build && cmake --build build -j2",
        "/usr/bin/python3 bench/run.py            # full run, rewrites docs/benchmarks.md and docs/bench-*.png",
        "/usr/bin/python3 bench/run.py --quick --out /tmp/bench   # < 1 min slice",
        "/usr/bin/python3 bench/run.py --compare 'other-tool {in} {out}'   # add another tool's rows",
        "```",
        "",
        "Options: `--max-faces N` caps the generated sizes, `--no-profile` skips callgrind, "
        "`--repeat N` sets the runs per small case, `--build-dir` picks the engine build. Raw "
        "numbers of the last full run: bench/results.json. The smoke test "
        "tests/test_benchmark.py runs the quick slice into a temporary folder.",
        "",
    ]
    (out / "benchmarks.md").write_text("\n".join(md))
    return images
