"""`brdfpy render` (what a bare `brdfpy` runs): the built-in scene, a user's mesh, the canonical scene,
options and errors — as a person at a terminal sees them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import brdfpy
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
        "kd=0.2,0.8,0.2",
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
    assert (lit[:, 1] > lit[:, 0]).all()  # the green kd shows


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
        (["--model", "lambert", "--param", "kd=-1"], "kd"),
        (["--light", "laser:0,0,0"], "--light"),
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


def _exit_status(args: list[str]) -> int:
    """The status `brdfpy ARGS` exits with (argparse's own errors raise SystemExit(2))."""
    try:
        return cli.main(args)
    except SystemExit as e:
        return int(e.code or 0)


@pytest.mark.parametrize("size", ["0x0", "100x0", "0x100", "5x-10"])
def test_a_zero_or_negative_size_is_a_usage_error_not_a_traceback(tmp_path, capsys, size):
    out = tmp_path / "x.png"
    assert _exit_status(["render", "--size", size, "-q", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--size" in err and "at least 1" in err and size in err
    assert not out.exists()
    # As a user at a terminal sees it: no traceback.
    r = subprocess.run(
        [sys.executable, "-m", "brdfpy", "render", "--size", size], capture_output=True, text=True
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr and "--size" in r.stderr


def test_a_missing_mesh_file_is_reported_as_the_mesh_option(tmp_path, capsys):
    missing = tmp_path / "nope.ply"
    assert cli.main(["render", "--mesh", str(missing), "-q", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert f"--mesh: no such file: {str(missing)!r}" in err
    assert "path:" not in err  # the library's internal argument name
    assert cli.main(["render", "--mesh", "builtin:teapot", "-q", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "--mesh" in err and "teapot" in err and "name:" not in err


def test_an_obj_index_out_of_range_counts_vertices_in_english(tmp_path, capsys):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
    assert cli.main(["render", "--mesh", str(bad), "-q", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "the file has 3 vertices" in err and "vertexs" not in err
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    assert cli.main(["render", "--mesh", str(bad), "-q", "-o", str(tmp_path / "x.png")]) == 2
    assert "the file has 1 vertex)" in capsys.readouterr().err


def _mesh_render(tmp_path: Path, *extra: str) -> np.ndarray:
    out = tmp_path / "m.png"
    args = ["render", "--mesh", "builtin:cow", "--no-floor", "--size", "96x64", "--samples", "1", "-q"]
    assert cli.main([*args, *extra, "-o", str(out)]) == 0
    return _png(out).astype(int)


def test_param_and_naming_the_default_model_keep_the_default_red_material(tmp_path):
    # The cow's default material is cook_torrance's red plastic; any --param changes only that parameter.
    default = _mesh_render(tmp_path)
    named = _mesh_render(tmp_path, "--model", "cook_torrance")
    assert np.array_equal(default, named)
    rough = _mesh_render(tmp_path, "--param", "roughness=0.6")
    for img in (default, rough):
        cow = img[img.sum(axis=2) > 120]  # the background is (20, 22, 29)
        assert len(cow) > 300, "the cow is (almost) black"
        assert np.median(cow[:, 0]) > np.median(cow[:, 1]) + 30  # red, not gray or black
    assert not np.array_equal(default, rough)


def test_help_says_how_the_defaults_differ_from_scene_render():
    r = subprocess.run([sys.executable, "-m", "brdfpy", "render", "--help"], capture_output=True, text=True)
    flat = " ".join(r.stdout.split())
    assert "4 samples per pixel, shadows, ACES" in flat
    assert "Scene.render()" in flat and "1 sample, no shadows, clamp" in flat
    doc = " ".join((brdfpy.Scene.render.__doc__ or "").split())
    assert "one sample per pixel, no shadows" in doc and "samples=4" in doc and 'tonemap="aces"' in doc


def _light_render(tmp_path: Path, *lights: str) -> np.ndarray:
    out = tmp_path / "l.png"
    args = ["render", "--mesh", "builtin:cow", "--size", "64x48", "--samples", "1", "-q", "--no-shadows"]
    for light in lights:
        args += ["--light", light]
    assert cli.main([*args, "-o", str(out)]) == 0
    return _png(out)


def test_light_from_is_the_same_light_as_dir_with_the_opposite_direction(tmp_path):
    a = _light_render(tmp_path, "dir:-1,-1,-0.5:2,2,2")
    b = _light_render(tmp_path, "from:1,1,0.5:2,2,2")
    assert np.array_equal(a, b)
    # From the other side it is another image.
    assert not np.array_equal(a, _light_render(tmp_path, "dir:1,-1,-0.5:2,2,2"))


def test_a_bare_light_direction_is_refused_as_ambiguous(tmp_path, capsys):
    assert cli.main(["render", "--light", "1,1,1", "-q", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "ambiguous" in err and "dir:1,1,1" in err and "from:1,1,1" in err


def test_param_without_a_model_in_a_scene_of_several_materials_is_refused(tmp_path, capsys):
    # It used to be ignored without a word.
    for scene in ("builtin", "canonical"):
        args = ["render", "--scene", scene, "--param", "roughness=0.1", "-q", "-o", str(tmp_path / "x.png")]
        assert cli.main(args) == 2
        err = capsys.readouterr().err
        assert "--param" in err and "--model" in err
    assert not (tmp_path / "x.png").exists()
