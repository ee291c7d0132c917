"""The EN 1991-2 check's report as a person sees it: ``report.html`` rendered by a real headless browser (Debian's
Chromium, which ``.ci/run`` installs), its screenshot checked for the verdict banner (the pass or fail colour of
``en1991_report.py`` over a band of the page's top) and for the envelope figure (Matplotlib's first line colour,
only in the embedded plot).  Skipped, with the reason, where no browser is installed."""
from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from exudyn_wheelrail.scenarios import en1991_dynamic as E
from exudyn_wheelrail.scenarios.en1991_report import FAIL_COLOUR, PASS_COLOUR
from exudyn_wheelrail.scenarios.sweep import SerialExecutor

BROWSER = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)
#: Matplotlib's first colour cycle entry (tab:blue), the first train's line
FIRST_LINE_RGB = (0x1F, 0x77, 0xB4)


def _pixels_near(img, rgb, tol=6):
    return np.all(np.abs(img[..., :3].astype(int) - np.array(rgb)) <= tol, axis=-1)


@pytest.mark.skipif(BROWSER is None, reason="no Chromium installed (.ci/run installs Debian's chromium)")
def test_the_report_renders_with_its_verdict_and_its_figure(tmp_path):
    import matplotlib.image as mpimg
    bridge = tmp_path / "bridge.toml"
    bridge.write_text("[bridge]\nspans_m = [15.0]\nEI_Nm2 = 1.0e10\nmass_kg_per_m = 12000.0\n"
                      "structure = 'steel_composite'\n")
    check = E.DynamicCheck(bridge=E.read_bridge_file(bridge), max_line_speed_kmh=200.0, trains=("A1",),
                           speeds_kmh=(160.0, 200.0, 240.0))
    summary = E.run_dynamic_check(check, tmp_path / "out", executor=SerialExecutor(), progress=None)
    shot = tmp_path / "shot.png"
    cmd = [BROWSER, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           f"--user-data-dir={tmp_path / 'profile'}", "--hide-scrollbars", "--window-size=1100,2200",
           f"--screenshot={shot}", (tmp_path / "out" / "report.html").as_uri()]
    subprocess.run(cmd, check=True, capture_output=True, timeout=120)
    img = (mpimg.imread(shot) * 255).round().astype(np.uint8)
    banner = PASS_COLOUR if summary["verdict"] == "pass" else FAIL_COLOUR
    other = FAIL_COLOUR if banner == PASS_COLOUR else PASS_COLOUR
    top = img[:400]
    # the banner: a block of its colour (at least 300 x 30 px) near the top, none of the other verdict's colour
    assert _pixels_near(top, banner).sum() > 300 * 30
    assert _pixels_near(img, other).sum() == 0
    # the figure: the first train's line drawn in the embedded plot, below the banner — a line across the plot's
    # width (~850 px here, 1-2 px wide, anti-aliased): at least 300 pixels within 30 of its colour in each channel
    # (the page has no other blue; measured ~680)
    assert _pixels_near(img[400:], FIRST_LINE_RGB, tol=30).sum() > 300
