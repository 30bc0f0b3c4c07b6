"""`brdfpy render` (what a bare `brdfpy` runs): the built-in scene, a user's mesh, the canonical scene,
options and errors — as a person at a terminal sees them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from brdfpy import cli
from PIL import Image

SMALL = ["--size", "96x54", "--samples", "1"]


def _png(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        assert im.format == "PNG" and im.mode == "RGB"
        return np.asarray(im)


def test_bare_command_renders_the_builtin_scene_into_brdfpy_render_png(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert cli.main(["--size", "160x90", "--quiet"]) == 0
    img = _png(tmp_path / "brdfpy-render.png")
    assert img.shape == (90, 160, 3)
    # Several differently coloured objects and a lit floor: many distinct colours, nothing blown out.
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 1000
    assert (img == 255).all(axis=2).mean() < 0.01


def test_render_reports_what_it_wrote(tmp_path, capsys):
    out = tmp_path / "scene.png"
    assert cli.main(["render", *SMALL, "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert str(out) in text and "96x54" in text and "triangles" in text and "3 lights" in text


def test_user_mesh_with_a_chosen_model_shading_and_lights(tmp_path):
    obj = tmp_path / "tet.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    out = tmp_path / "tet.png"
    args = [
        "render",
        "--mesh",
        str(obj),
        "--model",
        "lambert",
        "--param",
        "albedo=0.2,0.8,0.2",
        "--shading",
        "flat",
        "--light",
        "dir:-1,-1,-1:2,2,2",
        "--no-floor",
        "--no-shadows",
        *SMALL,
        "-o",
        str(out),
        "-q",
    ]
    assert cli.main(args) == 0
    img = _png(out).astype(int)
    lit = img[(img.sum(axis=2) > 30)]
    assert len(lit) > 100
    assert (lit[:, 1] > lit[:, 0]).all()  # the green albedo shows


def test_canonical_scene_prints_scene_md_check_value(tmp_path, capsys):
    out = tmp_path / "c.png"
    assert cli.main(["render", "--scene", "canonical", "--size", "64x48", "-o", str(out)]) == 0
    assert "centre pixel [232, 151, 127]" in capsys.readouterr().out
    assert tuple(_png(out)[24, 32]) == (232, 151, 127)


def test_shading_modes_ao_and_negative_coordinates_are_accepted(tmp_path):
    for extra in (["--shading", "gouraud"], ["--shading", "quadratic"], ["--ao"], ["--eye", "-2,1.5,3"]):
        out = tmp_path / "x.png"
        assert cli.main(["render", *SMALL, "-q", "-o", str(out), *extra]) == 0, extra
        assert _png(out).shape == (54, 96, 3)


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["--mesh", "does-not-exist.ply"], "does-not-exist.ply"),
        (["--model", "velvet"], "velvet"),
        (["--model", "lambert", "--param", "albedo=-1"], "albedo"),
        (["--light", "laser:0,0,0"], "--light"),
        (["--size", "0x10"], "width"),
    ],
)
def test_bad_options_exit_2_with_a_message_naming_the_problem(tmp_path, capsys, args, word):
    assert cli.main(["render", *args, "-q", "-o", str(tmp_path / "x.png")]) == 2
    assert word in capsys.readouterr().err


def test_malformed_mesh_file_is_an_error_not_a_crash(tmp_path, capsys):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    assert cli.main(["render", "--mesh", str(bad), "-q", "-o", str(tmp_path / "x.png")]) == 2
    assert "bad.obj" in capsys.readouterr().err


def test_long_renders_show_progress_on_stderr(tmp_path):
    # Run as a user would, in a separate process; the bar appears once a render takes longer than 0.3 s.
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "brdfpy",
            "render",
            "--size",
            "1280x720",
            "--samples",
            "16",
            "--ao",
            "-o",
            str(tmp_path / "big.png"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    assert "100 %" in r.stderr and "[" in r.stderr


def test_help_lists_render_and_its_options():
    r = subprocess.run([sys.executable, "-m", "brdfpy", "render", "--help"], capture_output=True, text=True)
    assert r.returncode == 0
    for opt in ("--mesh", "--model", "--param", "--shading", "--light", "--size", "--ao", "--shadows", "-o"):
        assert opt in r.stdout
