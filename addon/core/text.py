# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures as a designer reads them (no bpy): shares and percentages with
sensible digits, durations, plural words, lines wrapped to a width, and the
missing-library message in one sentence."""

import math
import re


def plural(n, one, many):
    return "%d %s" % (n, one if n == 1 else many)


def share(x):
    """A share 0..1 as a percentage that never claims more than is true: 1 is
    "100 %" and nothing short of it rounds up to it, 0 is "0 %" and nothing
    above it rounds down to it ("99.9 %", "0.4 %", "< 0.1 %")."""
    p = 100.0 * float(x)
    if not p > 0.0:
        return "0 %"
    if p >= 100.0:
        return "100 %"
    if p < 0.1:
        return "< 0.1 %"
    if p < 1.0:
        return "%.1f %%" % (math.floor(p * 10.0) / 10.0)
    if p > 99.0:
        return "%.1f %%" % min(math.floor(p * 10.0) / 10.0, 99.9)
    return "%.0f %%" % min(max(round(p), 1), 99)


def percent(p, digits=2):
    """A percentage of any size with `digits` significant digits at most,
    never in exponent notation: "12 %", "0.24 %", "< 0.01 %", "0 %"."""
    p = float(p)
    if p == 0.0 or not math.isfinite(p):
        return "0 %" if p == 0.0 else "%s %%" % p
    sign = "-" if p < 0 else ""
    a = abs(p)
    if a < 0.01:
        return "%s< 0.01 %%" % sign
    decimals = max(0, digits - 1 - int(math.floor(math.log10(a))))
    return "%s%.*f %%" % (sign, min(decimals, 2), a)


def signed_percent(p):
    """A change in percent with its sign: "+4.4 %", "-99.8 %", "-0.02 %"."""
    p = float(p)
    if abs(p) >= 100.0:
        return "%+.0f %%" % p
    if abs(p) >= 0.1:
        return "%+.1f %%" % p
    text = percent(p)
    return text if text.startswith(("-", "0 ")) else "+" + text


def duration(seconds):
    if seconds < 90:
        return "%.0f s" % max(seconds, 1)
    if seconds < 5400:
        return "%.0f min" % (seconds / 60)
    return "%.1f h" % (seconds / 3600)


def milliseconds(ms):
    return "%.0f ms" % ms if ms < 10000 else "%.1f s" % (ms / 1000.0)


def wrap(text, fits):
    """Lines of `text` broken between words; fits(line) -> bool says whether a
    line fits (a character count, or a measured width). A word longer than a
    whole line is broken where the line ends."""
    if isinstance(fits, int):
        width = fits

        def fits(line):
            return len(line) <= width

    lines, line = [], ""
    for word in text.split():
        candidate = (line + " " + word).strip()
        if fits(candidate):
            line = candidate
            continue
        if line:
            lines.append(line)
        while not fits(word) and len(word) > 1:
            cut = max(1, max(i for i in range(1, len(word)) if fits(word[:i]) or i == 1))
            lines.append(word[:cut])
            word = word[cut:]
        line = word
    if line:
        lines.append(line)
    return lines


def designer_words(sentence):
    """The engine's sentence with its mathematician's words for curvature in
    a designer's ("mean |defect|" is the mean curvature)."""
    return sentence.replace("|defect|", "curvature").replace("|angle defect|", "curvature")


def library_message(err):
    """The missing or mismatched library in one short sentence (the full text,
    with the paths looked at, goes to the console)."""
    abi = re.search(r"ABI version (\d+) but this add-on needs (\d+)", err)
    if abi:
        return (
            "The engine library has ABI version %s but this add-on needs %s: install the "
            "add-on and its library from the same zip" % abi.groups()
        )
    if "not found" in err:
        return (
            "Engine library not found: reinstall the add-on from its zip, or point "
            "DEVELOPABLE_LIBRARY at libdevelopable.so (details in the console)"
        )
    return "The engine library could not be loaded: reinstall the add-on (details in the console)"
