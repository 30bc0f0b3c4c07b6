"""The `brdfpy` command: what a person sees when they run it (the gallery PNG, --help, errors)."""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import brdfpy
import numpy as np
import pytest
from brdfpy import cli, gallery
from PIL import Image

ROOT = Path(__file__).resolve().parent.parent


def _png(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        assert im.format == "PNG"
        assert im.mode == "RGB"
        return np.asarray(im)


def test_gallery_command_writes_the_gallery_of_every_model_into_the_current_folder(
    tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    assert cli.main(["gallery"]) == 0
    img = _png(tmp_path / "brdfpy-gallery.png")
    out = capsys.readouterr().out
    assert "brdfpy-gallery.png" in out and f"{len(brdfpy.models())} models" in out
    # One cell per model: the sheet has at least as many sphere-sized cells as models.
    cols = len(brdfpy.models())
    assert img.shape[0] * img.shape[1] >= cols * 160 * 160


def test_gallery_option_o_writes_where_asked_and_every_sphere_is_lit(tmp_path):
    out = tmp_path / "sub.png"
    names = ["lambert", "cook_torrance", "ward"]
    assert (
        cli.main(["gallery", "--models", ",".join(names), "--size", "48", "--columns", "3", "-o", str(out)])
        == 0
    )
    img = _png(out).astype(int)
    assert img.shape[1] == 3 * (48 + 2 * 8)  # three columns of sphere + padding
    background = img[0, 0]
    for k in range(3):
        cell = img[8 : 8 + 48, k * 64 + 8 : k * 64 + 56]
        lit = np.abs(cell - background).sum(axis=-1) > 30
        assert lit.mean() > 0.2, f"sphere {names[k]} is not visible"


def test_light_from_the_right_makes_the_right_half_of_a_lambert_sphere_brighter(tmp_path):
    out = tmp_path / "g.png"
    args = ["--models", "lambert", "--size", "64", "--ambient", "0", "-o", str(out)]
    assert cli.main(["gallery", *args, "--light", "from:1,0,0.2"]) == 0
    img = _png(out).astype(float)
    sphere = img[8 : 8 + 64, 8 : 8 + 64].sum(axis=-1)
    assert sphere[:, 40:56].mean() > sphere[:, 8:24].mean() + 50
    # The same light by its direction of travel (the spelling of `brdfpy render --light dir:`).
    assert cli.main(["gallery", *args, "--light", "dir:-1,0,-0.2"]) == 0
    assert np.array_equal(_png(out).astype(float), img)
    # Negative components work without "=" (argparse would otherwise take them for an option).
    assert cli.main(["gallery", *args, "--light", "from:-1,0,0.2"]) == 0
    flipped = _png(out).astype(float)[8 : 8 + 64, 8 : 8 + 64].sum(axis=-1)
    assert flipped[:, 8:24].mean() > flipped[:, 40:56].mean() + 50


def test_gallery_default_light_comes_from_the_upper_right_front(tmp_path):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    base = ["gallery", "--models", "lambert", "--size", "32"]
    assert cli.main([*base, "-o", str(a)]) == 0
    assert cli.main([*base, "--light", "from:1,1,1", "-o", str(b)]) == 0
    assert np.array_equal(_png(a), _png(b))


def test_a_bare_gallery_light_direction_is_refused_as_ambiguous(tmp_path, capsys):
    # Before, `--light X,Y,Z` meant the direction toward the light in the gallery and nothing in render.
    assert cli.main(["gallery", "--light", "1,0,0.2", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "ambiguous" in err and "dir:1,0,0.2" in err and "from:1,0,0.2" in err
    assert not (tmp_path / "x.png").exists()


def test_render_gallery_takes_a_directional_light_and_explains_three_numbers():
    with pytest.raises(TypeError, match=r"DirectionalLight\(\(-1.0, 0.0, 0.0\)\)"):
        gallery.render_gallery(["lambert"], light=(1, 0, 0), size=16)
    with pytest.raises(ValueError, match="exposure"):
        gallery.render_gallery(["lambert"], light=brdfpy.DirectionalLight((-1, 0, 0), 2.0), size=16)
    right = gallery.render_gallery(["lambert"], light=brdfpy.DirectionalLight((-1, 0, 0)), size=32, ambient=0)
    sphere = right[8:40, 8:40].astype(float).sum(axis=-1)
    assert sphere[:, 20:30].mean() > sphere[:, 2:12].mean() + 50


def test_param_changes_the_rendering_and_is_validated(tmp_path, capsys):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    base = ["gallery", "--models", "lambert", "--size", "32"]
    assert cli.main([*base, "-o", str(a)]) == 0
    assert cli.main([*base, "--param", "lambert.kd=0.9,0.1,0.1", "-o", str(b)]) == 0
    red = _png(b).astype(int)[8 + 16, 8 + 16]
    assert red[0] > red[1] + 60 and not np.array_equal(_png(a), _png(b))
    assert cli.main([*base, "--param", "lambert.kd=-1", "-o", str(b)]) == 2
    assert "kd" in capsys.readouterr().err
    assert cli.main([*base, "--param", "kd=0.5", "-o", str(b)]) == 2
    assert "MODEL.KEY=VALUE" in capsys.readouterr().err
    assert cli.main([*base, "--param", "ward.alpha_x=0.1", "-o", str(b)]) == 2
    assert "ward" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--models", "nope"], "nope"),
        (["--light", "dir:0,0,0"], "light"),
        (["--light", "dir:1,2"], "light"),
        (["--light", "point:1,2,3"], "--light"),
        (["--light", "dir:0,0,-1:2,2,2"], "exposure"),
        (["--size", "3"], "size"),
        (["--ambient", "-1"], "ambient"),
    ],
)
def test_bad_options_exit_with_status_2_and_name_the_problem(tmp_path, capsys, args, needle):
    assert cli.main(["gallery", *args, "-o", str(tmp_path / "x.png")]) == 2
    assert needle in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def test_every_tonemap_operator_renders(tmp_path):
    for op in brdfpy.tonemap.OPERATORS:
        out = tmp_path / f"{op}.png"
        assert (
            cli.main(["gallery", "--models", "phong", "--size", "24", "--tonemap", op, "-o", str(out)]) == 0
        )
        assert _png(out).shape[2] == 3


def test_help_explains_the_options():
    text = subprocess.run(
        [sys.executable, "-m", "brdfpy", "gallery", "--help"], capture_output=True, text=True, check=True
    ).stdout
    for opt in ("--models", "--param", "--light", "--size", "--columns", "--tonemap", "-o"):
        assert opt in text
    top = subprocess.run(
        [sys.executable, "-m", "brdfpy", "--help"], capture_output=True, text=True, check=True
    )
    assert "gallery" in top.stdout


def test_console_script_is_installed():
    # The script of *this* interpreter's install (its scripts folder, or beside the executable in a venv),
    # not whichever `brdfpy` comes first on PATH, which may belong to another interpreter.
    folders = [sysconfig.get_path("scripts"), str(Path(sys.executable).parent)]
    exe = shutil.which("brdfpy", path=os.pathsep.join(folders))
    if exe is None:
        pytest.skip("no brdfpy console script beside this interpreter (package not installed with pip)")
    done = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True)
    assert brdfpy.__version__ in done.stdout


def test_sphere_geometry_gives_unit_normals_facing_the_viewer_and_tangents_around_the_vertical_axis():
    mask, n, t = gallery.sphere_geometry(33)
    assert mask.shape == (33, 33) and n.shape == (mask.sum(), 3) == t.shape
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, rtol=1e-6)
    assert (n[:, 2] > 0).all()
    np.testing.assert_allclose(np.einsum("ij,ij->i", n, t), 0.0, atol=1e-6)
    # Circles of latitude around +y: horizontal, and vanishing nowhere inside the disc but near its top and
    # bottom (|n_y| -> 1), not at its centre.
    assert np.all(t[:, 1] == 0)
    assert np.linalg.norm(t[np.abs(n[:, 1]) < 0.9], axis=1).min() > 0.4
    # Row 0 is the top of the image: its normals point up (+y).
    assert n[: mask[0].sum(), 1].min() > 0.5


def test_the_eval_benchmark_runs_and_writes_json(tmp_path):
    spec = importlib.util.spec_from_file_location("bench_run", ROOT / "benchmarks" / "run.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.main(["eval", "--quick", "--out", str(tmp_path)]) == 0
    data = json.loads((tmp_path / "eval.json").read_text())
    models = {r["model"] for r in data["results"]}
    assert {"lambert", "blinn_phong", "cook_torrance_ggx_smith_schlick"} <= models
    for r in data["results"]:
        assert r["evals_per_s"] > 0 and r["oracle_evals_per_s"] > 0 and r["floor_evals_per_s"] > 0
