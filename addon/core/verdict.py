# SPDX-License-Identifier: GPL-3.0-or-later
"""What a run's result means for the user (no bpy). The engine judges its
result (dev_stats: result, unchanged_reason, worse_figures, result_message,
the flat / ruled / crumpled shares, the move limit it used); this module
words that judgement and adds what only the add-on knows: the job the user
picked (so that advice never names the job that just ran), whether the
user's faces are flat pieces already (the engine sees only triangles), and
what to try next."""

from . import presets
from .text import percent, plural, share, signed_percent

# dev_stats.result / unchanged_reason / worse_figures (native/api/developable.h).
RESULT_UNCHANGED = 1
ALREADY_DEVELOPABLE, DEVELOPABLE_PIECEWISE, ALREADY_FLAT = 1, 2, 3
NO_VISIBLE_GAIN, NO_BETTER_ITERATE, REJECTED = 4, 5, 6
WORSE_MEAN_DEFECT, WORSE_MAX_DEFECT, WORSE_FLAT_SHARE, WORSE_RULED_SHARE, WORSE_TURNED_FACES = 1, 2, 4, 8, 16
# A curvature gathered on the seams (mean or largest |defect| up): expected of
# a closed surface made flat in pieces (Gauss-Bonnet), and the shape is usable.
GATHERED = WORSE_MEAN_DEFECT | WORSE_MAX_DEFECT

# The result is called crumpled when more than this share of its flat vertices
# are not ruled (zero curvature bought with a zigzag of facets: the sheet
# unfolds, but looks faceted, not bent). Measured with the General job
# (docs/addon.md, "Flat, but crumpled"): the families of devkit/families.py
# (seeds 100-101, 2000 faces) end with 0-4 % of their flat vertices crumpled;
# before the engine's ruled finish (docs/method.md) the demo cone band 10 %,
# the demo half cylinder 30 %, a noisy square-to-round duct 18 %, human_woman
# 45 %; the finish takes the two demos to 1 % and under.
CRUMPLED_SHARE = 0.1

KINDS = ("IMPROVED", "GATHERED", "CRUMPLED", "WORSE", "UNCHANGED", "DEVELOPABLE")
TITLES = {
    "IMPROVED": "Improved",
    "GATHERED": "Curvature on seams",
    "CRUMPLED": "Flat, but crumpled",
    "WORSE": "A figure got worse",
    "UNCHANGED": "Nothing changed",
    "DEVELOPABLE": "Already developable",
}


class Facts:
    """What the add-on knows of a run beyond the engine's stats.
    closed: no boundary; sheet: one piece shaped like a sheet (a disc or a
    band, checks.sheet_like), which a one-piece job suits; job: the preset key the run used (CUSTOM when
    changed by hand); segmentation: "AUTO" / "OFF" / "ON"; keep_boundary: the
    boundary was pinned; move_limit: the user's limit in words ("1 %",
    "10 edge lengths", "" for none); flat_faces: the number of flat pieces
    when the user's faces are flat pieces already (checks.flat_faced), else 0;
    size: the mesh's bounding-box diagonal in the engine's units; polish: the
    angle polish setting ("AUTO", "ON", "OFF")."""

    def __init__(
        self,
        closed=False,
        sheet=True,
        job="GENERAL",
        segmentation="AUTO",
        keep_boundary=False,
        move_limit="1 %",
        flat_faces=0,
        size=0.0,
        polish="AUTO",
    ):
        self.closed = closed
        self.sheet = sheet and not closed
        self.job = job
        self.segmentation = segmentation
        self.keep_boundary = keep_boundary
        self.move_limit = move_limit
        self.flat_faces = flat_faces
        self.size = size
        self.polish = polish


class Verdict:
    """level: "INFO" or "WARNING"; kind: one of KINDS; text: the add-on's
    words; engine: the engine's own sentence (may be empty); summary: the
    figures in one line; key_value: where the "Developable" key is set (0:
    the result is kept but not shown)."""

    def __init__(self, level, kind, text, engine="", summary="", key_value=1.0):
        self.level, self.kind, self.text = level, kind, text
        self.engine, self.summary, self.key_value = engine, summary, key_value

    @property
    def title(self):
        return TITLES[self.kind]

    def report(self):
        """The one line of Blender's report."""
        line = self.text
        if self.engine:
            line += " Engine: " + self.engine
        if self.summary:
            line += " [%s]" % self.summary
        return line


def nothing_to_do(reason, flat_threshold):
    """The words for a reason that means there was nothing to do, or None."""
    return {
        ALREADY_DEVELOPABLE: "it is already developable",
        DEVELOPABLE_PIECEWISE: "it is already developable piecewise: its curvature sits on the seams between "
        "flat pieces",
        ALREADY_FLAT: "every vertex is already flat (curvature under %g rad)" % flat_threshold,
    }.get(reason)


def _job(key):
    return "the job '%s'" % presets.LABELS[key]


def _tips(facts, turned=False, crumpled=False, patches=1):
    """What to try next, never the job that just ran nor a switch already on.
    A crumpled result (flat vertices that are facets, not one bend) comes
    from the angle polish: without it the deformation bends the mesh
    smoothly, leaving a few vertices curved (measured with the General job:
    the demo cone band 90 -> 100 % flat and ruled, the demo half cylinder
    70 -> 96 %, a noisy square-to-round duct 82 -> 89 %)."""
    tips = []
    limit = " (now %s)" % facts.move_limit if facts.move_limit else ""
    if turned:
        if facts.move_limit:
            tips.append("a smaller 'Shape may move'%s" % limit)
        if not facts.keep_boundary and not facts.closed:
            tips.append("'Keep the boundary'")
        return tips
    if crumpled and facts.polish != "OFF":
        tips.append("'Angle polish: Off' in Advanced (smooth bends instead of facets; a few vertices may stay curved)")
    if not facts.sheet and facts.segmentation != "ON":
        why = "a closed surface cannot flatten as one piece" if facts.closed else "an object, not one sheet"
        tips.append(_job("OBJECT") + " (%s)" % why)
    elif crumpled and facts.sheet and patches > 1 and facts.segmentation != "OFF" and facts.job != "SHEET":
        tips.append(_job("SHEET") + " (one piece)")
    if facts.move_limit and not (crumpled and tips):
        tips.append("a larger 'Shape may move'%s" % limit)
    if not facts.sheet and facts.segmentation == "ON":
        tips.append("more pieces (Advanced > Number of pieces)")
    return tips


def _try(tips):
    return " Try %s." % " or ".join(tips) if tips else ""


def _summary(stats, facts):
    """The figures in one line. An unchanged result is the input: its figures
    are the input's (the engine's "after" shares of an input it returned as
    already developable are not all filled in)."""
    if stats["result"] == RESULT_UNCHANGED:
        return "flat %s, flat and ruled %s, unchanged, %.0f ms" % (
            share(stats["flat_share_before"]),
            share(stats["ruled_share_before"]),
            stats["time_total_ms"],
        )
    return "flat %s \u2192 %s, flat and ruled %s \u2192 %s, curvature %s, moved at most %s of its size, %s, %.0f ms" % (
        share(stats["flat_share_before"]),
        share(stats["flat_share_after"]),
        share(stats["ruled_share_before"]),
        share(stats["ruled_share_after"]),
        signed_percent(stats["change_percent"]),
        percent(100.0 * stats["max_vertex_move"] / facts.size if facts.size > 0 else 0.0),
        plural(stats["faces_turned_over"], "face turned over", "faces turned over"),
        stats["time_total_ms"],
    )


def verdict(name, stats, facts):
    """The Verdict of one run. stats: the engine's dev_stats as a dict."""
    flat_threshold = stats["flat_threshold"] or 1e-3
    summary = _summary(stats, facts)
    engine = stats.get("result_message", "").strip()
    if stats["result"] == RESULT_UNCHANGED:
        words = nothing_to_do(stats["unchanged_reason"], flat_threshold)
        if words is None and facts.flat_faces:
            # The engine saw triangles and found nothing to improve; the user's faces say why. Its
            # sentence (e.g. "try a larger tolerance") no longer applies, so it is not repeated.
            engine = ""
            words = (
                "it is already developable piecewise: its %s flat, its curvature sits on the edges where "
                "they meet (Unfold Pattern lays them out as they are)"
                % plural(facts.flat_faces, "face is", "faces are")
            )
        if words:
            return Verdict("INFO", "DEVELOPABLE", "%s: nothing to do, %s." % (name, words), engine, summary)
        return Verdict(
            "WARNING",
            "UNCHANGED",
            "%s: nothing changed, no better shape was found within the limits.%s" % (name, _try(_tips(facts))),
            engine,
            summary,
        )
    worse = stats["worse_figures"]
    if worse & ~GATHERED:
        what = []
        if worse & WORSE_FLAT_SHARE:
            what.append(
                "fewer vertices are flat (%s \u2192 %s)"
                % (share(stats["flat_share_before"]), share(stats["flat_share_after"]))
            )
        if worse & WORSE_RULED_SHARE:
            what.append(
                "fewer are flat and ruled (%s \u2192 %s: the rest crumpled into facets)"
                % (share(stats["ruled_share_before"]), share(stats["ruled_share_after"]))
            )
        if worse & WORSE_TURNED_FACES:
            what.append(plural(stats["faces_turned_over"], "face turned over", "faces turned over"))
        if worse & WORSE_MEAN_DEFECT:
            what.append("the mean curvature grew (%s)" % signed_percent(stats["change_percent"]))
        if worse & WORSE_MAX_DEFECT:
            what.append(
                "the largest curvature grew (%.3g \u2192 %.3g rad)"
                % (stats["max_defect_before"], stats["max_defect_after"])
            )
        tips = _tips(
            facts,
            turned=bool(worse & WORSE_TURNED_FACES),
            crumpled=bool(worse & WORSE_RULED_SHARE),
            patches=stats["patches"],
        )
        return Verdict(
            "WARNING",
            "WORSE",
            "%s got worse: %s. The result is kept in the shape key 'Developable' at 0 (slide it to look).%s"
            % (name, "; ".join(what), _try(tips)),
            engine,
            summary,
            key_value=0.0,
        )
    flat_after = stats["flat_share_after"]
    if flat_after > 0 and stats["crumpled_share_after"] > CRUMPLED_SHARE * flat_after:
        tips = _tips(facts, crumpled=True, patches=stats["patches"])
        return Verdict(
            "WARNING",
            "CRUMPLED",
            "%s: %s of its vertices are flat, but only %s flat and ruled: the rest are crumpled into facets "
            "(zero curvature, but not one smooth bend: it looks faceted).%s"
            % (name, share(flat_after), share(stats["ruled_share_after"]), _try(tips)),
            engine,
            summary,
        )
    if worse & GATHERED:
        why = (
            "a closed surface keeps its total curvature (Gauss-Bonnet): made flat in pieces, it gathers on the seams"
            if facts.closed
            else "the curvature the flat vertices gave up gathered on fewer others"
        )
        grew = []
        if worse & WORSE_MEAN_DEFECT:
            grew.append("the mean curvature grew (%s)" % signed_percent(stats["change_percent"]))
        if worse & WORSE_MAX_DEFECT:
            grew.append(
                "the largest grew (%.3g \u2192 %.3g rad)" % (stats["max_defect_before"], stats["max_defect_after"])
            )
        return Verdict(
            "WARNING",
            "GATHERED",
            "%s: flat %s \u2192 %s, but %s: %s. Slide 'Developable' to 0 to compare."
            % (name, share(stats["flat_share_before"]), share(flat_after), " and ".join(grew), why),
            engine,
            summary,
        )
    return Verdict("INFO", "IMPROVED", "%s: %s" % (name, summary), "", "")
