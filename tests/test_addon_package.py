"""The add-on as shipped: manifest rules, the zip's contents, its native
dependencies, installing and enabling it in Blender."""
import ast
import re
import subprocess
import sys
import zipfile

import pytest

from blender_support import MODULE, REPO, module_blenders, scenario, validate_manifest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = None

SYSTEM_LIBS = re.compile(
    r"^(linux-vdso|ld-linux|libc\.so|libm\.so|libstdc\+\+\.so|libgcc_s\.so|" r"libpthread\.so|libdl\.so)"
)


@pytest.fixture(scope="module")
def manifest():
    if tomllib is None:
        pytest.skip("tomllib needs Python 3.11")
    with open(REPO / "blender_manifest.toml", "rb") as f:
        return tomllib.load(f)


# The rules of Blender's extension manifest, schema 1.0.0 (Blender 4.2+,
# docs.blender.org/manual/en/latest/advanced/extensions/getting_started.html),
# as its own validation (`blender --command extension validate`) applies them.
REQUIRED_KEYS = {
    "schema_version",
    "id",
    "version",
    "name",
    "tagline",
    "maintainer",
    "type",
    "blender_version_min",
    "license",
}
OPTIONAL_KEYS = {"website", "tags", "blender_version_max", "copyright", "platforms", "wheels", "permissions", "build"}
SEMVER = re.compile(
    r"(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)"
    r"(?:-[0-9A-Za-z-]+(?:\.[0-9A-Za-z-]+)*)?(?:\+[0-9A-Za-z-]+(?:\.[0-9A-Za-z-]+)*)?"
)
PLATFORMS = {"windows-x64", "windows-arm64", "macos-x64", "macos-arm64", "linux-x64"}
ADDON_TAGS = {
    "3D View",
    "Add Curve",
    "Add Mesh",
    "Animation",
    "Bake",
    "Camera",
    "Compositing",
    "Development",
    "Game Engine",
    "Geometry Nodes",
    "Grease Pencil",
    "Import-Export",
    "Lighting",
    "Material",
    "Modeling",
    "Mesh",
    "Node",
    "Object",
    "Paint",
    "Pipeline",
    "Physics",
    "Render",
    "Rigging",
    "Scene",
    "Sculpt",
    "Sequencer",
    "System",
    "Text Editor",
    "Tracking",
    "User Interface",
    "UV",
}
# SPDX identifiers of the licences the Extensions Platform accepts for add-ons
# (GPL-compatible, since add-ons link against Blender's GPL Python API).
LICENSES = {
    "GPL-2.0-or-later",
    "GPL-3.0-or-later",
    "LGPL-2.1-or-later",
    "LGPL-3.0-or-later",
    "MIT",
    "MIT-0",
    "BSD-2-Clause",
    "BSD-3-Clause",
    "Apache-2.0",
    "MPL-2.0",
    "Zlib",
    "BSL-1.0",
    "CC0-1.0",
    "CC-BY-4.0",
    "CC-BY-SA-4.0",
}


def version_tuple(text):
    match = SEMVER.fullmatch(text)
    assert match, "%r is not a semantic version" % text
    return tuple(int(g) for g in match.groups())


def plain_text(value, limit=None):
    """A non-empty string without control characters or surrounding blanks."""
    return (
        isinstance(value, str)
        and value == value.strip()
        and value
        and not any(ord(c) < 32 for c in value)
        and (limit is None or len(value) <= limit)
    )


def test_manifest_follows_the_extension_schema(manifest):
    m = manifest
    assert REQUIRED_KEYS <= set(m), REQUIRED_KEYS - set(m)
    assert set(m) <= REQUIRED_KEYS | OPTIONAL_KEYS, set(m) - REQUIRED_KEYS - OPTIONAL_KEYS
    assert m["schema_version"] == "1.0.0"
    # id: a Python identifier without leading, trailing or doubled underscores,
    # and the package name the zip's folder and the tests use
    assert m["id"].isidentifier() and "__" not in m["id"], m["id"]
    assert not m["id"].startswith("_") and not m["id"].endswith("_"), m["id"]
    assert m["id"] == MODULE
    version_tuple(m["version"])
    for key in ("name", "maintainer"):
        assert plain_text(m[key]), key
    # tagline: at most 64 characters, ending in a letter or digit (no punctuation)
    assert plain_text(m["tagline"], 64) and m["tagline"][-1].isalnum(), m["tagline"]
    assert m["type"] in ("add-on", "theme")
    assert version_tuple(m["blender_version_min"]) >= (4, 2, 0)
    if "blender_version_max" in m:
        assert version_tuple(m["blender_version_max"]) > version_tuple(m["blender_version_min"])
    assert isinstance(m["license"], list) and m["license"]
    for lic in m["license"]:
        assert lic.startswith("SPDX:") and lic[len("SPDX:") :] in LICENSES, lic
    if "platforms" in m:
        assert m["platforms"] and set(m["platforms"]) <= PLATFORMS, m["platforms"]
    if "tags" in m:
        assert isinstance(m["tags"], list) and set(m["tags"]) <= ADDON_TAGS, m["tags"]
    if "website" in m:
        assert re.match(r"https?://", m["website"]), m["website"]
    for reason in (m.get("permissions") or {}).values():
        assert plain_text(reason, 64) and reason[-1].isalnum(), reason


def test_manifest_platforms_are_those_of_the_shipped_library(manifest, addon_zip):
    """The zip ships one native library, built for one platform: the manifest
    must name exactly that one (Blender refuses to install it elsewhere)."""
    with zipfile.ZipFile(addon_zip) as z:
        header = z.read("%s/libdevelopable.so" % MODULE)[:20]
    assert header[:4] == b"\x7fELF" and header[4] == 2, "not a 64-bit ELF library"
    machine = int.from_bytes(header[18:20], "little" if header[5] == 1 else "big")
    platform = {62: "linux-x64", 183: "linux-arm64"}[machine]
    assert manifest["platforms"] == [platform]


def test_bl_info_matches_the_manifest(manifest):
    text = (REPO / "addon" / "__init__.py").read_text()
    version = re.search(r'"version":\s*\((\d+),\s*(\d+),\s*(\d+)\)', text).groups()
    assert ".".join(version) == manifest["version"]
    assert '"blender": (3, 4, 0)' in text


def test_package_uses_relative_imports_only():
    for path in (REPO / "addon").rglob("*.py"):
        text = path.read_text()
        assert not re.search(r"^\s*(from|import)\s+(addon|developable_mesh)\b", text, re.M), path
        for banned in ("import bgl", "face_maps", "calc_normals(", "calc_normals_split"):
            assert banned not in text, (path, banned)


def relative_imports(path):
    """The add-on's modules a module imports (from . import a, from .b import c,
    from .core import d, from .core.e import f), as dotted names in the package."""
    here = path.parent.relative_to(REPO / "addon").parts
    found = set()
    for dots, module, names in re.findall(r"^\s*from (\.+)([\w.]*) import \(?([\w, \n]+)\)?", path.read_text(), re.M):
        base = list(here[: len(here) - (len(dots) - 1)]) if len(dots) > 1 else list(here)
        parts = base + (module.split(".") if module else [])
        if module:
            found.add(".".join(parts))
        else:
            found |= {".".join(parts + [n.strip()]) for n in names.split(",") if n.strip()}
    return {name for name in found if (REPO / "addon" / (name.replace(".", "/") + ".py")).exists()}


def module_order():
    """CORE_MODULES + BLENDER_MODULES of the package's __init__: its modules in import order."""
    tree = ast.parse((REPO / "addon" / "__init__.py").read_text())
    lists = {
        node.targets[0].id: ast.literal_eval(node.value)
        for node in tree.body
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") in ("CORE_MODULES", "BLENDER_MODULES")
    }
    return list(lists["CORE_MODULES"]) + list(lists["BLENDER_MODULES"])


def imported_modules():
    """Every module of the package reached from its __init__'s lists, with what they import."""
    todo = set(module_order())
    seen = set()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        todo |= relative_imports(REPO / "addon" / (name.replace(".", "/") + ".py"))
    return seen


def test_core_imports_no_bpy_and_nothing_outside_core():
    """addon/core is the bpy-free part: it imports neither bpy nor the Blender
    modules, and the package imports nothing at module level (so that
    `from addon.core import native` works in any Python)."""
    for path in (REPO / "addon" / "core").glob("*.py"):
        text = path.read_text()
        assert not re.search(r"^\s*(import|from)\s+(bpy|bmesh|mathutils|blf)\b", text, re.M), path
        assert all(name.startswith("core.") for name in relative_imports(path)), (path, relative_imports(path))
    code = (
        "import sys; sys.path.insert(0, %r)\n"
        "from addon.core import native, checks, verdict, text, estimate, jobs, presets, colours\n"
        "assert 'bpy' not in sys.modules\n" % str(REPO)
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_no_import_circle():
    """Each module imports only modules listed before it in __init__'s order."""
    order = module_order()
    assert sorted(order) == sorted(imported_modules()), (order, imported_modules())
    for i, name in enumerate(order):
        imports = relative_imports(REPO / "addon" / (name.replace(".", "/") + ".py"))
        assert imports <= set(order[:i]), (name, imports - set(order[:i]))


def needed_libraries(library):
    return re.findall(
        r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]",
        subprocess.run(["readelf", "-d", str(library)], capture_output=True, text=True, check=True).stdout,
    )


def test_zip_holds_the_addon_and_nothing_else(addon_zip):
    """One folder: the package's modules (each reached from __init__.py), the
    manifest, the licence and the engine; no test or demo code."""
    with zipfile.ZipFile(addon_zip) as z:
        names = [n for n in z.namelist() if not n.endswith("/")]
    assert {n.split("/")[0] for n in names} == {MODULE}, names
    shipped = {n.split("/", 1)[1] for n in names}
    modules = {n[:-3].replace("/", ".") for n in shipped if n.endswith(".py")}
    assert modules == imported_modules() | {"__init__", "core.__init__"}, modules
    others = shipped - {m.replace(".", "/") + ".py" for m in modules}
    assert others <= {"blender_manifest.toml", "LICENSE", "libdevelopable.so"}, others
    assert {"blender_manifest.toml", "libdevelopable.so"} <= others


def test_engine_needs_only_the_system_runtime(build_dir):
    """docs/addon.md: libdevelopable.so links nothing beyond the C/C++ runtime
    (Eigen is header-only, OpenMesh is the tool's), so the zip bundles nothing
    else and installs on any Linux with Blender."""
    needed = needed_libraries(build_dir / "lib" / "libdevelopable.so")
    assert needed, "readelf found no NEEDED entry"
    assert all(SYSTEM_LIBS.match(dep) for dep in needed), needed


def test_zip_library_loads_with_what_it_finds(addon_zip, tmp_path):
    """Extracted alone, the shipped library resolves every dependency (ldd:
    nothing "not found"), each a system runtime library."""
    with zipfile.ZipFile(addon_zip) as z:
        z.extractall(tmp_path)
    out = subprocess.run(
        ["ldd", str(tmp_path / MODULE / "libdevelopable.so")], capture_output=True, text=True, check=True
    ).stdout
    lines = [line.strip() for line in out.splitlines() if line.strip()]
    assert lines
    for line in lines:
        assert "not found" not in line, line
        assert SYSTEM_LIBS.match(line.split()[0].split("/")[-1]), line


def test_zip_installs_and_enables(blender_env, installed_addon_dir):
    r = scenario(blender_env, "install")
    assert r["has_operator"]
    assert r["module"].split(".")[-1] == MODULE
    assert r["library"] == str(installed_addon_dir / "libdevelopable.so"), r["library"]
    assert not r["library_error"]
    assert r["version"]
    assert len(r["panels"]) == 3
    # max_move is set from 'Shape May Move' (properties.DERIVED_PARAMETERS), whose
    # default is the General job's 1 % of the size, the engine's default; the
    # move limit goes once, in that unit, so the tolerance in edge lengths is 0
    # (no limit) unless 'Limit in Edge Lengths' is ticked. Every other field is
    # an operator property.
    derived = {"max_move", "tolerance"}
    for name in r["param_names"]:
        assert name in r["operator_properties"] or name in derived, name
    # The operator's defaults are the engine's (grid_resolution 0 = "the engine's default").
    props, engine = r["property_defaults"], r["defaults"]
    assert set(props) == set(engine)
    assert props["max_move"] == pytest.approx(0.01) == pytest.approx(engine["max_move"])
    assert props["tolerance"] == 0.0
    for k in engine:
        if k in derived or (k == "grid_resolution" and props[k] == 0):
            continue
        assert props[k] == pytest.approx(engine[k]), k


def _header_struct(name):
    text = (REPO / "native" / "api" / "developable.h").read_text()
    body = re.search(r"typedef struct %s \{(.*?)\} %s;" % (name, name), text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    return re.findall(r"^\s*(int32_t|int64_t|double|uint8_t|char)\s+(\w+)\s*(?:\[(\d+)\])?\s*;", body, re.M)


def test_ctypes_binding_matches_the_header():
    import ctypes

    from addon.core import native

    ctype = {"int32_t": ctypes.c_int32, "int64_t": ctypes.c_int64, "double": ctypes.c_double, "uint8_t": ctypes.c_uint8}
    for struct in ("dev_params", "dev_stats"):
        header = [(n, ctypes.c_char * int(size) if t == "char" else ctype[t]) for t, n, size in _header_struct(struct)]
        binding = list(getattr(native, struct)._fields_)
        assert [n for n, _ in header] == [n for n, _ in binding], struct
        for (name, want), (_, have) in zip(header, binding):
            assert ctypes.sizeof(want) == ctypes.sizeof(have) and getattr(want, "_type_", want) == getattr(
                have, "_type_", have
            ), (struct, name)
    abi = int(
        re.search(r"#define DEV_ABI_VERSION (\d+)", (REPO / "native" / "api" / "developable.h").read_text()).group(1)
    )
    assert native.ABI_VERSION == abi


@pytest.mark.parametrize(
    "line", sorted(module_blenders()) or [pytest.param("none", marks=pytest.mark.skip("no bpy wheel installed"))]
)
def test_zip_passes_that_blenders_own_extension_validator(addon_zip, line):
    code, out = validate_manifest(addon_zip, module_blenders()[line])
    assert code == 0, out
    assert "error" not in out.lower(), out


def test_zip_installs_and_enables_on_every_blender(any_blender_env):
    """3.4: the legacy add-on path; 4.2+: the extensions path (bl_ext.user_default.*)."""
    r = scenario(any_blender_env, "install")
    assert r["has_operator"] and not r["library_error"] and r["version"]
    if any_blender_env["DEVELOPABLE_TEST_BLENDER_NAME"] == "3.4":
        assert r["module"] == MODULE
    else:
        assert r["module"] == "bl_ext.user_default." + MODULE, r["module"]
        assert "/extensions/user_default/%s/" % MODULE in r["library"], r["library"]
