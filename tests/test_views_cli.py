"""``brdfpy plot`` (and the argument checks of ``brdfpy explore``): files written, views chosen, bad input
refused with a message and exit status 2."""

from __future__ import annotations

from pathlib import Path

import brdfpy
import pytest
from brdfpy import cli
from brdfpy.measured import Tabulated
from PIL import Image

pytest.importorskip("matplotlib", reason="brdfpy[plot] (matplotlib) is not installed")


@pytest.mark.parametrize("view", ["polar", "lobe", "slice", "albedo", "sphere", "all"])
def test_plot_writes_a_png_of_each_view(
    view: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / f"{view}.png"
    args = ["plot", "cook_torrance,phong", "--param", "cook_torrance.roughness=0.2", "--view", view]
    assert cli.main([*args, "--theta-i", "30", "-o", str(out), "--dpi", "50"]) == 0
    with Image.open(out) as img:
        assert img.format == "PNG" and min(img.size) > 100
    assert f"wrote {out}" in capsys.readouterr().out


def test_plot_writes_svg_and_reads_a_measured_table(tmp_path: Path) -> None:
    table = tmp_path / "ct.binary"
    Tabulated.from_model(brdfpy.model("cook_torrance", roughness=0.3), (16, 16, 32)).save_merl(table)
    out = tmp_path / "slice.svg"
    assert cli.main(["plot", str(table), "--view", "slice", "-o", str(out)]) == 0
    assert out.read_text().lstrip().startswith("<?xml")


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["plot", "nope", "--view", "polar"], "unknown model"),
        (["plot", "lambert", "--view", "polar", "--theta-i", "95"], "theta_i"),
        (["plot", "lambert", "--view", "polar", "--theta-i", "-5"], "theta_i"),
        (["plot", "cook_torrance", "--param", "roughness=nan", "--view", "polar"], "roughness"),
        (["plot", "lambert", "--view", "polar", "-o", "x.jpg"], ".png or .svg"),
        (["plot", ",", "--view", "polar"], "MODEL"),
        (["explore", "lambert", "--port", "70000", "--no-browser"], "--port"),
    ],
)
def test_bad_input_exits_2_with_the_message(
    args: list[str],
    words: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert cli.main(args) == 2
    assert words in capsys.readouterr().err


def test_an_unknown_view_is_an_argparse_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        cli.main(["plot", "lambert", "--view", "radar"])
    assert e.value.code == 2 and "radar" in capsys.readouterr().err


def test_a_truncated_measured_table_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    table = tmp_path / "cut.binary"
    Tabulated.from_model(brdfpy.model("lambert"), (8, 8, 16)).save_merl(table)
    table.write_bytes(table.read_bytes()[:-100])
    assert cli.main(["plot", str(table), "--view", "slice", "-o", str(tmp_path / "s.png")]) == 2
    err = capsys.readouterr().err
    assert "expected" in err and "bytes" in err
