"""The wheel installs and works without Rust: run by ``scripts/test.sh`` in a fresh virtual environment where
the wheel (``BRDFPY_EXPECT_WHEEL``, its path) is installed and cargo and rustc are off the PATH. Elsewhere
(an editable install in a developer's environment) these tests are skipped, saying why."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from importlib import metadata
from pathlib import Path

import brdfpy
import numpy as np
import pytest

WHEEL = os.environ.get("BRDFPY_EXPECT_WHEEL")
SOURCE_TREE = Path(__file__).resolve().parent.parent

pytestmark = pytest.mark.skipif(
    not WHEEL, reason="runs against an installed wheel (scripts/test.sh sets BRDFPY_EXPECT_WHEEL)"
)


def test_brdfpy_is_imported_from_the_installed_wheel_not_the_source_tree():
    site = Path(sysconfig.get_paths()["purelib"]).resolve()
    where = Path(brdfpy.__file__).resolve()
    ext = Path(brdfpy._brdfpy.__file__).resolve()
    assert site in where.parents and site in ext.parents, (where, ext)
    assert SOURCE_TREE not in where.parents and SOURCE_TREE not in ext.parents
    # One compiled module for every CPython >= 3.9: the stable ABI.
    assert ext.name == "_brdfpy.abi3.so", ext.name


def test_no_rust_toolchain_is_reachable():
    assert shutil.which("cargo") is None and shutil.which("rustc") is None


def test_the_wheel_is_abi3_manylinux_and_holds_stubs_but_no_sources():
    assert WHEEL is not None
    name = Path(WHEEL).name
    assert "-cp39-abi3-manylinux_" in name, name
    with zipfile.ZipFile(WHEEL) as z:
        files = z.namelist()
        wheel_meta = next(f for f in files if f.endswith(".dist-info/WHEEL"))
        tags = [
            line.split(": ", 1)[1]
            for line in z.read(wheel_meta).decode().splitlines()
            if line.startswith("Tag:")
        ]
    assert tags and all(t.startswith("cp39-abi3-manylinux_") for t in tags), tags
    for needed in ("brdfpy/__init__.py", "brdfpy/_brdfpy.pyi", "brdfpy/py.typed", "brdfpy/_brdfpy.abi3.so"):
        assert needed in files, needed
    assert not any(f.endswith(".rs") or f.startswith("tests/") for f in files)
    # The installed distribution is that wheel's, with its console script.
    dist = metadata.distribution("brdfpy")
    assert dist.version == brdfpy.__version__
    assert any(ep.name == "brdfpy" for ep in dist.entry_points)


def test_the_installed_library_evaluates_and_renders():
    m = brdfpy.model("cook_torrance")
    f = m.eval([0.0, 0.6, 0.8], [0, 0, 1], [0, 0, 1])
    assert f.shape == (3,) and np.all(np.isfinite(f)) and f[0] > f[1]  # the red default
    scene = brdfpy.Scene()
    scene.add(brdfpy.icosphere(3), m)
    scene.add_light(brdfpy.DirectionalLight())
    img = scene.render(brdfpy.Camera.perspective((0, 0, 3)), 64, 48)
    assert img.rgb.shape == (48, 64, 3) and img.covered_pixels > 500


def test_the_installed_console_script_renders(tmp_path):
    exe = shutil.which("brdfpy")
    assert exe is not None and Path(exe).parent == Path(sys.executable).parent
    out = tmp_path / "r.png"
    done = subprocess.run(
        [exe, "render", "--size", "64x36", "--samples", "1", "-q", "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert out.stat().st_size > 1000
