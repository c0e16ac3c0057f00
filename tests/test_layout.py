"""The engine's layout (docs/architecture.md): native/ in one folder per part, each
including only the parts below it, and code small enough to read: no source file over
900 lines, no function over 120."""
import pathlib
import re

import pytest

NATIVE = pathlib.Path(__file__).resolve().parents[1] / "native"

# What each part may include besides itself (native/CMakeLists.txt draws the same arrows).
ALLOWED = {
    "core": set(),
    "ideal_curve": {"core"},
    "deformation": {"core"},
    "segmentation": {"core"},
    "pattern": {"core"},
    "pipeline": {"core", "ideal_curve", "deformation", "segmentation"},
    "api": {"core", "pipeline", "pattern"},
    "tool": {"api"},
    "fuzz": {"api"},
}
MAX_FILE_LINES = 900
MAX_FUNCTION_LINES = 120
# Sources allowed over the limits: none since issue 36. Kept as sets so that a test failure
# names what went over.
LONG_FILES = set()
LONG_FUNCTIONS = set()


def sources():
    return sorted(p for p in NATIVE.rglob("*") if p.suffix in (".h", ".cpp"))


def test_every_source_is_in_a_part():
    loose = [p.name for p in sources() if p.parent == NATIVE or p.relative_to(NATIVE).parts[0] not in ALLOWED]
    assert loose == []


@pytest.mark.parametrize("part", sorted(ALLOWED))
def test_includes_run_one_way(part):
    climbing = []
    for path in sorted((NATIVE / part).glob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        for line in path.read_text().splitlines():
            m = re.match(r'\s*#include "([a-z_]+)/[a-z_]+\.h"', line)
            if m and m.group(1) != part and m.group(1) not in ALLOWED[part]:
                climbing.append("%s: %s" % (path.relative_to(NATIVE), line.strip()))
    assert climbing == []


def test_no_source_file_is_too_long():
    long = {str(p.relative_to(NATIVE)) for p in sources() if len(p.read_text().splitlines()) > MAX_FILE_LINES}
    assert long == LONG_FILES


def _strip(text):
    """The text with comments, strings and character literals blanked (line breaks kept)."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def function_lengths(text):
    """{(first line of a function definition, its name): its length in lines}, for the outermost
    function bodies (a brace block opened after a parameter list, not inside another function)."""
    text = _strip(text)
    lengths, stack, statement_start = {}, [], 0  # stack: (is_function, line of the header's start)
    line = 1
    for i, ch in enumerate(text):
        if ch == "\n":
            line += 1
        elif ch == "{":
            header = text[statement_start:i]
            in_function = any(f for f, _ in stack)
            is_function = (
                not in_function
                and ")" in header
                and not re.search(r"\b(class|struct|enum|namespace|union)\b[^()]*$", header)
            )
            first = line - header.lstrip().count("\n")
            name = re.findall(r"([A-Za-z_][A-Za-z_0-9:]*)\s*\(", header)
            stack.append((is_function, (first, name[0].split("::")[-1] if name else "?")))
            statement_start = i + 1
        elif ch == "}":
            if stack:
                is_function, (first, name) = stack.pop()
                if is_function:
                    lengths[(first, name)] = line - first + 1
            statement_start = i + 1
        elif ch == ";":
            statement_start = i + 1
    return lengths


def test_function_lengths_are_measured():
    text = (
        "namespace a {\nstruct S {\n  int f() const {\n    return 1;\n  }\n};\nint g(int x)\n{\n"
        + "  auto l = [](int y) {\n    return y;\n  };\n  return l(x);\n}\n}  // namespace a\n"
    )
    assert function_lengths(text) == {(3, "f"): 3, (7, "g"): 7}


def test_no_function_is_too_long():
    long = set()
    for path in sources():
        for (first, name), length in function_lengths(path.read_text()).items():
            if length > MAX_FUNCTION_LINES:
                long.add("%s:%s" % (path.relative_to(NATIVE), name))
    assert long == LONG_FUNCTIONS
