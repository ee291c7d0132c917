"""Regenerate the stored reference of ``tests/test_rtri_regression.py`` (run from the repository root)::

    python tests/data/regenerate_rtri_reference.py

which runs exactly::

    python -m exudyn_wheelrail rtri --span 20 --speed-kmh 250 --solver newmark --dt 0.001 --duration 0.5 \\
        --delta-mm 12 --no-plots --out tests/data/rtri_reference

Configuration: the RTRI case, 20 m span, 250 km/h, Newmark (the paper's scheme), 1 ms, 500 steps (0.5 s: the
leading wheelset enters the deviation at 0.14 s, reaches its largest lateral excursion at ~0.32 s and leaves the
span at 0.48 s).  The deviation amplitude is raised to 12 mm (default assumption: 10 mm) so that the short run
covers a contact on the flange region (the default amplitude reaches only the flange root) — a regression
configuration that exercises both wheel regions, **not** a validation claim.  Regenerate only after a change of
the results has been understood and accepted; commit the new ``timeseries.csv`` and ``summary.json`` with it.
"""
import subprocess
import sys
from pathlib import Path

ARGS = ["rtri", "--span", "20", "--speed-kmh", "250", "--solver", "newmark", "--dt", "0.001", "--duration", "0.5",
        "--delta-mm", "12", "--no-plots"]
OUT = Path(__file__).resolve().parent / "rtri_reference"

if __name__ == "__main__":
    r = subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *ARGS, "--out", str(OUT)])
    sys.exit(r.returncode)
