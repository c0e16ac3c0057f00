"""The add-on as shipped: manifest rules, the zip's contents, its native
dependencies, installing and enabling it in Blender."""
import re
import subprocess
import sys
import zipfile

import pytest

from blender_support import (MODULE, REPO, addon_zip, any_blender_env, blender_env,  # noqa: F401
                             installed_addon_dir, module_blenders, scenario, validate_manifest)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = None

SYSTEM_LIBS = re.compile(r"^(linux-vdso|ld-linux|libc\.so|libm\.so|libstdc\+\+\.so|libgcc_s\.so|"
                         r"libpthread\.so|libdl\.so)")


@pytest.fixture(scope="module")
def manifest():
    if tomllib is None:
        pytest.skip("tomllib needs Python 3.11")
    with open(REPO / "blender_manifest.toml", "rb") as f:
        return tomllib.load(f)


def test_manifest_follows_the_extension_rules(manifest):
    m = manifest
    assert m["schema_version"] == "1.0.0"
    assert m["id"].isidentifier() and m["id"] == MODULE
    assert re.fullmatch(r"(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)", m["version"])
    assert m["version"] == "0.1.0"
    assert m["name"]
    tag = m["tagline"]
    assert 0 < len(tag) <= 64 and tag[-1].isalnum(), tag
    assert m["type"] == "add-on"
    assert m["maintainer"]
    assert m["blender_version_min"] == "4.2.0"
    assert isinstance(m["license"], list) and m["license"]
    assert all(lic.startswith("SPDX:") for lic in m["license"])
    assert "SPDX:GPL-3.0-or-later" in m["license"]
    assert m["platforms"] == ["linux-x64"]
    assert isinstance(m["tags"], list) and m["tags"]
    assert set(m["tags"]) <= {"3D View", "Add Curve", "Add Mesh", "Animation", "Bake", "Camera",
                              "Compositing", "Development", "Game Engine", "Geometry Nodes",
                              "Grease Pencil", "Import-Export", "Lighting", "Material", "Modeling",
                              "Mesh", "Node", "Object", "Paint", "Pipeline", "Physics", "Render",
                              "Rigging", "Scene", "Sculpt", "Sequencer", "System", "Text Editor",
                              "Tracking", "User Interface", "UV"}


def test_bl_info_matches_the_manifest(manifest):
    text = (REPO / "addon" / "__init__.py").read_text()
    version = re.search(r'"version":\s*\((\d+),\s*(\d+),\s*(\d+)\)', text).groups()
    assert ".".join(version) == manifest["version"]
    assert '"blender": (3, 4, 0)' in text


def test_package_uses_relative_imports_only():
    for path in (REPO / "addon").glob("*.py"):
        text = path.read_text()
        assert not re.search(r"^\s*(from|import)\s+(addon|developable_mesh)\b", text, re.M), path
        for banned in ("import bgl", "face_maps", "calc_normals(", "calc_normals_split"):
            assert banned not in text, (path, banned)


def test_zip_holds_one_addon_folder(addon_zip):
    with zipfile.ZipFile(addon_zip) as z:
        names = z.namelist()
    tops = {n.split("/")[0] for n in names}
    assert tops == {MODULE}, tops
    for needed in ("__init__.py", "blender_manifest.toml", "native.py", "operators.py",
                   "panels.py", "properties.py", "mesh_io.py", "writeback.py",
                   "libdevelopable.so"):
        assert "%s/%s" % (MODULE, needed) in names, needed
    # whatever the engine links beyond the system runtime (OpenMesh's
    # libOpenMeshCore.so.9.0 when it is linked) is bundled beside it
    lib = addon_zip.parent.parent / "lib" / "libdevelopable.so"
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]",
                        subprocess.run(["readelf", "-d", str(lib)], capture_output=True,
                                       text=True, check=True).stdout)
    for dep in needed:
        if not SYSTEM_LIBS.match(dep):
            assert "%s/%s" % (MODULE, dep) in names, dep


def test_zip_library_needs_only_the_system_runtime(addon_zip, tmp_path):
    with zipfile.ZipFile(addon_zip) as z:
        z.extractall(tmp_path)
    folder = tmp_path / MODULE
    out = subprocess.run(["ldd", str(folder / "libdevelopable.so")], capture_output=True,
                         text=True, check=True).stdout
    for line in out.splitlines():
        line = line.strip()
        if not line:
            continue
        assert "not found" not in line, line
        name = line.split()[0]
        if SYSTEM_LIBS.match(name.split("/")[-1]):
            continue
        assert "=>" in line, line
        target = line.split("=>")[1].split("(")[0].strip()
        assert target.startswith(str(folder)), "%s resolves outside the add-on: %s" % (name, line)


def test_zip_installs_and_enables(blender_env, installed_addon_dir):
    r = scenario(blender_env, "install")
    assert r["has_operator"]
    assert r["module"].split(".")[-1] == MODULE
    assert r["library"] == str(installed_addon_dir / "libdevelopable.so"), r["library"]
    assert not r["library_error"]
    assert r["version"]
    assert len(r["panels"]) == 3
    for name in r["param_names"]:
        assert name in r["operator_properties"], name
    # The operator's defaults are the engine's (grid_resolution 0 = "the engine's default").
    props, engine = r["property_defaults"], r["defaults"]
    assert set(props) == set(engine)
    for k in engine:
        if k == "grid_resolution" and props[k] == 0:
            continue
        assert props[k] == pytest.approx(engine[k]), k


def _header_struct(name):
    text = (REPO / "native" / "developable.h").read_text()
    body = re.search(r"typedef struct %s \{(.*?)\} %s;" % (name, name), text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    return re.findall(r"^\s*(int32_t|int64_t|double|uint8_t|char)\s+(\w+)\s*(?:\[(\d+)\])?\s*;",
                      body, re.M)


def test_ctypes_binding_matches_the_header():
    import ctypes
    import importlib.util
    spec = importlib.util.spec_from_file_location("dev_native", REPO / "addon" / "native.py")
    native = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(native)
    ctype = {"int32_t": ctypes.c_int32, "int64_t": ctypes.c_int64, "double": ctypes.c_double,
             "uint8_t": ctypes.c_uint8}
    for struct in ("dev_params", "dev_stats"):
        header = [(n, ctypes.c_char * int(size) if t == "char" else ctype[t])
                  for t, n, size in _header_struct(struct)]
        binding = list(getattr(native, struct)._fields_)
        assert [n for n, _ in header] == [n for n, _ in binding], struct
        for (name, want), (_, have) in zip(header, binding):
            assert ctypes.sizeof(want) == ctypes.sizeof(have) and \
                getattr(want, "_type_", want) == getattr(have, "_type_", have), (struct, name)
    abi = int(re.search(r"#define DEV_ABI_VERSION (\d+)",
                        (REPO / "native" / "developable.h").read_text()).group(1))
    assert native.ABI_VERSION == abi


@pytest.mark.parametrize("line", sorted(module_blenders()) or
                         [pytest.param("none", marks=pytest.mark.skip("no bpy wheel installed"))])
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
