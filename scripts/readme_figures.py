"""Make the pictures of the README's "Looking at a BRDF" section (docs/images/*.png).

Every picture is made by exactly the two lines of code the README shows next to it (they are run here as
written), so that the README cannot drift from the library. The explorer's screenshot needs Debian's chromium,
chromium-driver and selenium (skipped otherwise).

Usage: ``python scripts/readme_figures.py`` (from the repository root; needs brdfpy[plot]).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "images"

#: (file, the two lines of code). Kept in the README verbatim.
FIGURES = [
    (
        "polar.png",
        'ax = brdfpy.plot.polar(["cook_torrance", "blinn_phong", "ward"], theta_i=30)\n'
        'ax.figure.savefig("polar.png", dpi=90)',
    ),
    (
        "lobe.png",
        'ax = brdfpy.plot.lobe("ward", theta_i=40, phi=30)\nax.figure.savefig("lobe.png", dpi=90)',
    ),
    (
        "slice.png",
        'ax = brdfpy.plot.half_diff_slice(brdfpy.model("cook_torrance", roughness=0.2, kd=0.3))\n'
        'ax.figure.savefig("slice.png", dpi=90)',
    ),
    (
        "albedo.png",
        'ax = brdfpy.plot.albedo_table("blinn_phong", "shininess", [1, 4, 16, 64, 256, 1024])\n'
        'ax.figure.savefig("albedo.png", dpi=90)',
    ),
    (
        "spheres.png",
        'axes = brdfpy.plot.lit_sphere(["phong", "blinn_phong", "ward", "ashikhmin_shirley"], theta_i=40)\n'
        'axes[0].figure.savefig("spheres.png", dpi=90)',
    ),
    (
        "dashboard.png",
        'fig = brdfpy.plot.dashboard(["blinn_phong", "ward"], theta_i=35)\n'
        'fig.savefig("dashboard.png", dpi=75)',
    ),
]


def main() -> int:
    import brdfpy
    import brdfpy.plot

    OUT.mkdir(parents=True, exist_ok=True)
    os.chdir(OUT)
    for name, code in FIGURES:
        exec(code, {"brdfpy": brdfpy})
        matplotlib.pyplot.close("all")
        print(f"wrote {OUT / name}")
    subprocess.run([sys.executable, "-m", "brdfpy", "gallery", "-o", str(OUT / "gallery.png")], check=True)
    sys.path.insert(0, str(ROOT / "tests"))
    import browser

    missing = browser.available()
    if missing:
        print(f"explorer screenshot skipped: {missing}")
        return 0
    with browser.server("blinn_phong,ward") as url, browser.browser(1460, 1500) as d:
        browser.open_page(d, url)
        browser.set_value(d, "θ_i", 35.0, "Slider")
        time.sleep(2)
        d.save_screenshot(str(OUT / "explorer.png"))
    print(f"wrote {OUT / 'explorer.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
